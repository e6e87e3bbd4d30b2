"""A lockstep member's rules: what a node taking part in lockstep
simulated time does with each grant, and how it counts the messages it
receives against those the other members reported sending.

Every node that keeps time under lockstep takes part (the simulators,
the filters, the bag player, the courses) through this one side of the
protocol; the owner of simulated time (sim_clock) and the protocol's
whole argument (why nothing can wait forever) are in
rbx1_nav.sim_time.lockstep. The ROS side of a member is
rbx1_nav.sim_time.member_ros. Times are integer nanoseconds; no
rospy here (test/unit/test_lockstep.py).
"""
import collections

__all__ = ['Follower', 'MessageLedger', 'Inbox', 'Report', 'RESEND',
           'LOST_MESSAGES', 'STALLED', 'WAIT_WARNING', 'POLL', 'HANDLE', 'REPEAT', 'BACK',
           'STALE', 'NO_TICK', 'ALIGN', 'aligned', 'Reminder']

#: Wall seconds a member waits for a grant, or the owner for a report,
#: before sending its last message again.
RESEND = 0.5
#: Wall seconds a member waits for counted messages from a sender that is
#: no longer connected to it (and, by the master, no longer publishes the
#: topic) before taking them as lost. While the sender is connected its
#: messages are on their way, in order: they are awaited however long a
#: loaded machine takes, so what a member takes never depends on the load.
LOST_MESSAGES = 1.0
#: Wall seconds after which a member takes counted messages from a sender
#: still connected as lost all the same: a backstop against a hang, with
#: a warning that names it, not a limit a loaded machine reaches (a member
#: connects for its counted messages at both ends before it joins:
#: rbx1_nav.sim_time.member_ros.Member.wait_for_inputs).
STALLED = 10.0
#: Wall seconds between the warnings of a member that keeps waiting for
#: counted messages from a connected sender.
WAIT_WARNING = 5.0
#: Wall seconds between a waiting member's checks that what it waits for
#: is still connected.
POLL = 0.1
#: A report's ``next`` when the member has no tick of its own (a filter
#: waiting for its first data): it is granted the next step, whatever it is.
NO_TICK = 0
#: ns: a course's first tick is at a multiple of this (:func:`aligned`).
#: 0.1 s holds a whole number of 10 ms clock steps, 20 ms simulator steps
#: (50 Hz, on a grid from zero: rbx1_nav.sim.loop_ros) and 50 ms course
#: ticks (20 Hz), so a course meets the same simulator steps between its
#: ticks whenever it joined, and ends the same to the last digit.
ALIGN = 100000000


def aligned(time_ns):
    """The first multiple of ALIGN at or after ``time_ns``."""
    return -(-time_ns // ALIGN) * ALIGN

#: What a member does with a grant (Follower.grant).
HANDLE, REPEAT, BACK, STALE = 'handle', 'repeat', 'back', 'stale'

#: A member's report: ``handled`` (ns) the step it answers (None when it
#: joins), ``next`` (ns) its next tick, ``every_step`` True for a
#: simulator, ``sent`` a dict {resolved topic: messages published so far}
#: of the topics it counts (a motion node's cmd_vel, a simulator's sensors,
#: a filter's estimate), ``leaving`` True on its last report, ``passive``
#: True for a member that follows time without driving it (a filter).
Report = collections.namedtuple(
    'Report', 'name handled next every_step sent leaving passive', defaults=(False,))


class Follower(object):
    """A member's side: what to do with each grant.

    Grants come from one owner at a time, named by its ``session``; within
    a session time only goes forward.
    """

    def __init__(self):
        self.session = None
        self.handled = None  # the last step handled (ns)

    def grant(self, session, time):
        """HANDLE a new step, REPEAT the report for one already handled (a
        grant sent again), BACK: a new owner starts before the last step
        handled (time moved back; the member starts again or gives up),
        STALE: an older grant of the same owner (refused)."""
        if session != self.session:
            self.session = session
            if self.handled is not None and time < self.handled:
                return BACK
            return HANDLE
        if self.handled is None or time > self.handled:
            return HANDLE
        return REPEAT if time == self.handled else STALE

    def handled_step(self, time):
        self.handled = time


class MessageLedger(object):
    """A member's count of the messages it received, per topic and sender,
    against the counts the other members reported sending (a simulator's
    commands, a filter's sensor messages)."""

    def __init__(self, topics):
        self.topics = set(topics)
        self.received = collections.Counter()  # (topic, sender) -> messages
        # Given up as lost on the way (less a restarted sender's old count).
        self.lost = collections.Counter()
        self.counted = {}  # (topic, sender) -> the count in the last grant
        # (topic, sender, link) -> [messages had (received + lost) before
        # the link's first, messages on it]: a link is one connection.
        self.links = {}

    def arrived(self, topic, sender, link=None):
        """A message from ``sender`` on ``topic``; ``link`` names the
        connection it came on (a node started again under its old name
        comes on a new one), None if unknown."""
        key = (topic, sender)
        if link is not None:
            self.links.setdefault(key + (link,), [self.received[key] + self.lost[key], 0])[1] += 1
        self.received[key] += 1

    def missing(self, counts):
        """[(topic, sender, how many)] of the messages reported in ``counts``
        ((topic, sender, count) triples) that have not arrived; topics this
        member does not subscribe to are not its business."""
        return [(topic, sender, count - have)
                for topic, sender, count in counts if topic in self.topics
                for have in [self.received[(topic, sender)] + self.lost[(topic, sender)]]
                if have < count]

    def settle(self, counts):
        """A member's first grant: the messages counted before it took part
        were sent before it listened (or to its predecessor); none of them
        is awaited."""
        for topic, sender, count in counts:
            if topic in self.topics:
                self.lost[(topic, sender)] = max(0, count - self.received[(topic, sender)])

    def restarts(self, counts):
        """Take a grant's ``counts``: a sender whose count went down is a
        node started again under the same name, counting from zero; the
        old one's messages (all arrived or lost: it had left) no longer
        count. Without this a simulator would take the new node's first
        commands as the old one's, and step without waiting for them.
        Where the links are known, the new node's messages are those on
        links opened after the old one's counted messages had all come:
        the old one's stop sent after its last report (it had left) is
        not taken for one of the new node's."""
        for topic, sender, count in counts:
            key = (topic, sender)
            before = self.counted.get(key, 0)
            if count < before:
                links = {k: v for k, v in self.links.items() if k[:2] == key}
                if links:
                    # The old links go; the new ones count from zero.
                    new = 0
                    for link, (first, n) in links.items():
                        del self.links[link]
                        if first >= before:
                            self.links[link] = [0, n]
                            new += n
                    self.lost[key] = new - self.received[key]
                else:
                    self.lost[key] -= before
            self.counted[key] = count

    def give_up(self, counts, gone=None):
        """Take the missing messages of ``counts`` as lost (only those of
        the (topic, sender) pairs in ``gone``, if given); return them."""
        missing = [(topic, sender, short) for topic, sender, short in self.missing(counts)
                   if gone is None or (topic, sender) in gone]
        for topic, sender, short in missing:
            self.lost[(topic, sender)] += short
        return missing


class Inbox(object):
    """A member's input messages, held until a grant counts them.

    Under lockstep a message published during the step being handled may
    or may not have arrived when the member reads its inputs; so a member
    that must give the same answer on every run (a filter, a course
    following a filter's transform) takes only the messages the grant
    counts, which were all sent before it, and keeps the others for a
    later grant. Messages from a sender that reports no count (not a
    member) are taken as they come.
    """

    def __init__(self, topics):
        self.ledger = MessageLedger(topics)
        self.held = collections.defaultdict(collections.deque)  # (topic, sender) -> items
        self.taken = collections.Counter()  # (topic, sender) -> items taken

    def arrived(self, topic, sender, item, link=None):
        self.ledger.arrived(topic, sender, link)
        self.held[(topic, sender)].append(item)

    def passed(self, topic, sender, link=None):
        """A message counted but not kept (its member is not taking part:
        nothing would take it, and an idle node must not hoard them)."""
        self.ledger.arrived(topic, sender, link)
        self.taken[(topic, sender)] += 1

    def take(self, counts, members, key, topic=None):
        """The items the grant's ``counts`` cover that were not taken
        before, plus every item from a sender not among the ``members``
        it is granted to, sorted by ``key(item)`` (then topic, sender and
        arrival): the same list on every run once
        :meth:`MessageLedger.missing` is empty.

        A sender granted this step may send meanwhile: what it sends
        waits for the grant that counts it, however early it arrives (its
        first messages too: no count yet counts 0). One not granted this
        step sends nothing tick by tick: what it sent past its count is
        not a member's (a node that is no member, or one that has left,
        such as a course's stop on its way out), taken as it comes. Items
        counted as lost are skipped. With ``topic``, that input's only."""
        counted = {(t, s): count for t, s, count in counts}
        out = []
        for source, queue in sorted(self.held.items()):
            if topic is not None and source[0] != topic:
                continue
            if source[1] in members:
                awaited = counted.get(source, 0) - self.ledger.lost[source]
                n = min(len(queue), max(0, awaited - self.taken[source]))
            else:
                n = len(queue)
            for index in range(n):
                out.append((key(queue[0]), source, index, queue.popleft()))
            self.taken[source] += n
        out.sort(key=lambda entry: entry[:3])
        return [entry[3] for entry in out]


class Reminder(object):
    """When a member that nothing grants steps to says so: ``first`` wall
    seconds into a wait, then every ``every`` seconds of the same wait
    (once a minute, not every few seconds, for a node left waiting).

    :meth:`due` takes the wall time now and answers the seconds waited
    when a warning is due, else None; :meth:`granted` ends the wait.
    """

    def __init__(self, first, every, now):
        self.first = first
        self.every = every
        self.granted(now)

    def granted(self, now):
        self.since = now
        self.next = now + self.first

    def due(self, now):
        if now < self.next:
            return None
        self.next = now + self.every
        return now - self.since
