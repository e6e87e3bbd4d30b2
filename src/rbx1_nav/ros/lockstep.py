"""The ROS side of lockstep simulated time (the rules: rbx1_nav.lockstep).

Lockstep is on when both ``/use_sim_time`` and ``/lockstep`` are true
(sim_clock.launch sets them); on a real robot nothing here runs.

:class:`TimeOwner` is sim_clock's part: it takes the members' reports on
REPORT_TOPIC, grants each step on GRANT_TOPIC and publishes ``/clock``.
:class:`Member` is a simulator's or a motion node's part: it joins, waits
for each grant naming it, reports the step handled, and leaves.
"""
import random
import threading
import time
import warnings

import rospy
import rospy.impl.simtime
from rosgraph_msgs.msg import Clock

from rbx1_nav.lockstep import (BACK, HANDLE, LOST_COMMANDS, REPEAT, RESEND,
                               SILENT, STALE, CommandLedger, Follower, Owner,
                               Report)
from rbx1_nav.msg import LockstepGrant, LockstepReport

# BACK and HANDLE: what Member.wait_grant returns, for its callers.
__all__ = ['BACK', 'HANDLE', 'GRANT_TOPIC', 'REPORT_TOPIC', 'GRANT_LIMIT',
           'STATE_LIMIT', 'FIRST_MEMBER', 'ClockPublisher', 'JoinError',
           'Member', 'TimeOwner', 'enabled', 'from_ns', 'keep_own_time',
           'publish', 'sender', 'synchronous_publisher', 'to_ns']

#: Global topics, like /clock: one owner of simulated time per master.
GRANT_TOPIC = '/lockstep_grant'
REPORT_TOPIC = '/lockstep_report'
#: Wall seconds between the owner's lines naming the members it waits for.
SLOW_MEMBER = 1.0
#: Wall seconds a motion node waits for its next grant before it takes the
#: clock as gone (more than SILENT: a member stuck elsewhere is dropped by
#: the owner first).
GRANT_LIMIT = SILENT + 1.0
#: Wall seconds a motion node waits for its simulator's state at a tick.
STATE_LIMIT = 1.0
#: Wall seconds sim_clock holds time at its start for a first member (a
#: simulator joins within a second; one of a sim_clock started again
#: joins once the new connections are up: over 5 s beside a loaded
#: test suite).
FIRST_MEMBER = 15.0


def enabled():
    """True when this run uses lockstep simulated time."""
    return bool(rospy.get_param('/use_sim_time', False)
                and rospy.get_param('/lockstep', False))


def to_ns(stamp):
    """rospy.Time -> integer nanoseconds."""
    return stamp.secs * 1000000000 + stamp.nsecs


def from_ns(ns):
    """Integer nanoseconds -> rospy.Time."""
    return rospy.Time(*divmod(int(ns), 1000000000))


def sender(msg):
    """The node name that published ``msg`` (rospy keeps it per message)."""
    return msg._connection_header['callerid']


def synchronous_publisher(topic, msg_class, **kwargs):
    """A publisher that writes each message before publish() returns, with
    no Nagle delay: lockstep waits for every message, so a hand-off to
    rospy's queue thread would only add latency to each step."""
    with warnings.catch_warnings():  # queue_size None is the point here
        warnings.simplefilter('ignore', SyntaxWarning)
        return rospy.Publisher(topic, msg_class, queue_size=None,
                               tcp_nodelay=True, **kwargs)


def publish(pub, msg):
    """Publish; False once rospy has closed its topics (shutting down)."""
    try:
        pub.publish(msg)
        return True
    except rospy.ROSException:
        if not rospy.core.is_shutdown_requested():
            raise
        return False


def keep_own_time():
    """Stop hearing /clock: from now on this node sets its ROS time itself
    (rospy.rostime._set_rostime, what rospy's /clock callback calls).

    Under /use_sim_time rospy subscribes every node to /clock. The node
    that publishes it, and a simulator, granted every step /clock carries,
    know each time before /clock tells them; hearing it again costs the
    publisher a socket write and the node a thread woken, which takes the
    GIL from the stepping thread, at every step. True if rospy's /clock
    subscription was there and is gone (otherwise /clock still sets the
    time, and a node setting it too does no harm)."""
    sub = getattr(rospy.impl.simtime, '_clock_sub', None)
    if sub is None:
        return False
    rospy.impl.simtime._clock_sub = None
    sub.unregister()
    return True


class ClockPublisher(object):
    """/clock, from the one node that publishes it: its own ROS time
    follows what it publishes instead of coming back over /clock
    (:func:`keep_own_time`)."""

    def __init__(self):
        self.pub = synchronous_publisher('/clock', Clock)
        self.own_time = keep_own_time()

    def publish(self, time_ns):
        """Publish ``time_ns``; False once rospy has closed its topics."""
        stamp = from_ns(time_ns)
        if self.own_time:
            rospy.rostime._set_rostime(stamp)
        return publish(self.pub, Clock(clock=stamp))


class TimeOwner(object):
    """sim_clock's side of lockstep: the one owner of simulated time.

    ``start`` and ``step`` (ns): the time already reached and the step
    taken when no member asks for a time; ``batch``: grant simulators only
    the motion nodes' ticks while any takes part (rbx1_nav.lockstep).
    """

    def __init__(self, start, step, batch=False, name='sim_clock'):
        self.name = name
        self.owner = Owner(start, step, batch)
        self.session = random.getrandbits(63) or 1
        self.cond = threading.Condition()
        self.seen = set()  # members whose report connection was listed
        self.plan = None      # sim_clock's pacing (run)
        self.planned = None   # (time ns, names, due wall s): the next step
        self.current = None   # (time ns, re-send at, warn at) of the step granted
        # Taken under self.cond when a step starts, released once its grant
        # and /clock are out: whichever thread sends them, a step's go out
        # before the next one's.
        self.sending = threading.Lock()
        self.clock = ClockPublisher()
        self.grant_pub = synchronous_publisher(GRANT_TOPIC, LockstepGrant)
        self.sub = rospy.Subscriber(REPORT_TOPIC, LockstepReport, self._on_report,
                                    queue_size=None, tcp_nodelay=True)

    def _on_report(self, msg):
        name = sender(msg)
        report = Report(name, to_ns(msg.handled), to_ns(msg.next), msg.every_step,
                        dict(zip(msg.cmd_topics, msg.cmd_counts)), msg.leaving)
        with self.cond:
            change, warning = self.owner.report(report)
            self.seen.add(name)  # its connection is listed: the report came over it
            start = self._next_step()
        if start:
            self._send_step(*start)
        if change:
            rospy.loginfo('%s: %s %s lockstep%s', self.name, name, change,
                          ' (simulator)' if msg.every_step and change == 'joined' else '')
        if warning:
            rospy.logwarn('%s: %s', self.name, warning)

    def _grant_message(self, time_ns, names):
        counts = self.owner.command_counts()
        return LockstepGrant(
            session=self.session, time=from_ns(time_ns), members=names,
            cmd_topics=[c[0] for c in counts], cmd_senders=[c[1] for c in counts],
            cmd_counts=[c[2] for c in counts])

    def _send(self, time_ns, names):
        return publish(self.grant_pub, self._grant_message(time_ns, names))

    def wait_for_members(self, limit):
        """Wait up to ``limit`` wall seconds for a first member, publishing
        meanwhile the start time on /clock (nodes wait for a first /clock
        before they join, and take it only once they have subscribed) and
        an empty grant (the members of an earlier sim_clock join at once
        when they see a new session)."""
        deadline = time.monotonic() + limit
        with self.cond:
            while not (self.owner.members or rospy.is_shutdown()
                       or time.monotonic() > deadline):
                self.clock.publish(self.owner.now)
                self._send(self.owner.now, [])
                self.cond.wait(0.05)

    def run(self, plan):
        """Own simulated time until shutdown.

        ``plan(next_grant, drives)``, sim_clock's pacing, gives (time ns,
        names, wall s to wait) of the next step from the Owner's
        next_grant() and drives(). Each step is granted to its names and
        published on /clock; the next is planned once all have reported.
        The thread whose report completes a step starts the next one when
        its time has come (a hand-off to this thread would cost every step
        a thread woken); this thread starts the ones that wait, and
        watches the members: it re-sends a grant to the silent ones every
        RESEND s and drops members that died or stay silent for SILENT s.
        """
        with self.cond:
            self.plan = plan
        while not rospy.is_shutdown():
            with self.cond:
                start = self._next_step()
                if not start:
                    due = self.planned[2] if self.planned else float('inf')
                    wait = min(0.05, max(0.0, due - time.monotonic()))
                    if not self.cond.wait(wait):
                        self._watch()
                    continue
            self._send_step(*start)

    def _next_step(self):
        """Under self.cond, once nothing is owed: plan the next step, and
        start it if its time has come; then return (time ns, grant or None)
        for the caller to send with _send_step, holding self.sending."""
        if self.plan is None or self.owner.owing():
            return None
        if self.planned is None:
            time_ns, names, wait = self.plan(self.owner.next_grant(), self.owner.drives())
            self.planned = (time_ns, names, time.monotonic() + wait)
        time_ns, names, due = self.planned
        now = time.monotonic()
        if now < due:
            self.cond.notify_all()  # run's thread starts it then
            return None
        self.planned = None
        names = self.owner.grant(time_ns, names, now)
        self.current = (time_ns, now + RESEND, now + SLOW_MEMBER)
        grant = self._grant_message(time_ns, names) if names else None
        self.sending.acquire()
        return time_ns, grant

    def _send_step(self, time_ns, grant):
        """The grant of a step just started, then its /clock (for everyone
        else: off the grant's path). Not under self.cond: a report that
        answers the grant before the send returns (this thread preempted
        by the member it woke) must not wait for it."""
        try:
            if grant is not None:
                publish(self.grant_pub, grant)
            self.clock.publish(time_ns)
        finally:
            self.sending.release()

    def _watch(self):
        """Under self.cond, every 50 ms (wall) while a step is owed: drop
        the members that died or stay silent, re-send the grant to the
        silent ones every RESEND s, and say who time waits for every
        SLOW_MEMBER s."""
        if not self.owner.owing():
            return
        time_ns, resend_at, warn_at = self.current
        now = time.monotonic()
        self._drop_disconnected()
        for name in self.owner.silent(now):
            self.owner.drop(name)
            rospy.logwarn('%s: %s has not handled the step at %.3f s for '
                          '%.0f s; going on without it until it reports '
                          'again', self.name, name, time_ns * 1e-9, SILENT)
        owing = self.owner.owing()
        if owing and now > resend_at:
            resend_at = now + RESEND
            self._send(time_ns, owing)
        if owing and now > warn_at:
            warn_at = now + SLOW_MEMBER
            rospy.logwarn('%s: simulated time waits at %.3f s for %s',
                          self.name, time_ns * 1e-9, ', '.join(owing))
        self.current = (time_ns, resend_at, warn_at)

    def _drop_disconnected(self):
        """Members whose report connection closed (the node died) leave."""
        connected = {c.callerid_pub for c in self.sub.impl.connections}
        members = set(self.owner.members)
        self.seen |= connected & members
        # A member that just joined may not have its connection listed yet.
        for name in sorted((members & self.seen) - connected):
            self.seen.discard(name)
            self.owner.drop(name)
            rospy.logwarn('%s: %s left lockstep without a word (node gone)',
                          self.name, name)


class JoinError(Exception):
    """A node could not join the lockstep; the message says why."""


class Member(object):
    """A lockstep member: a simulator (``every_step``) or a motion node.

    A simulator passes the resolved names of its cmd_vel topics in
    ``cmd_topics`` and counts each command that arrives with
    :meth:`command_from`; a motion node counts each one it sends with
    :meth:`sent`. Once it has joined, a simulator takes its ROS time from
    the grants, not /clock (:func:`keep_own_time`): it is named in every
    grant, and /clock moves only with them.

    A motion node waits for each of its ticks with :meth:`wait_grant`. A
    simulator passes ``step``: step(action, time ns) steps to a granted
    time (action HANDLE or BACK, as wait_grant returns) and returns its
    next tick (ns); :meth:`serve` then runs it.
    """

    def __init__(self, every_step=False, cmd_topics=(), step=None):
        self.name = rospy.get_name()
        self.every_step = every_step
        self.step = step
        self.busy = False       # a step being handled (serve)
        self.heard = None       # wall time of the last grant or step handled
        self.failure = None     # what step raised, for serve to raise
        self.follower = Follower()
        self.ledger = CommandLedger(cmd_topics)
        self.sent_counts = {}  # topic -> cmd_vel messages sent (motion node)
        self.settled = False   # a simulator's first grant handled
        self.cond = threading.Condition()
        # Orders the reports (report, leave from a shutdown hook, the
        # re-sends) apart from self.cond: the next grant can arrive before
        # the report's send returns (this thread preempted by the owner it
        # woke), and must not wait for it.
        self.sending = threading.RLock()
        self.grant = None       # the newest grant naming this node
        self.members = set()    # the names in the newest grant seen
        self.joined = self.left = False
        self.rejoin = False     # a new owner is there: send the report now
        self.last = None        # the last report, to send again
        self.own_time = False   # ROS time set from the grants (a simulator)
        self.pub = synchronous_publisher(REPORT_TOPIC, LockstepReport)
        self.sub = rospy.Subscriber(GRANT_TOPIC, LockstepGrant, self._on_grant,
                                    queue_size=None, tcp_nodelay=True)

    def _on_grant(self, msg):
        with self.cond:
            self.members = set(msg.members)
            named = self.name in self.members
            if named and self.step is None:
                self.grant = msg
                self.cond.notify_all()
            elif named:
                self.busy = True
            elif self.joined and msg.session != self.follower.session:
                # A new owner (sim_clock restarted): join it at once.
                self.rejoin = True
                self.cond.notify_all()
        if named and self.step is not None:
            self._handle(msg)

    def _handle(self, grant):
        """A simulator's step, in the thread that received its grant (see
        serve): the commands counted, the step, the report."""
        try:
            taken = self.failure is None and self._take(grant)
            if taken:
                action, time_ns, _ = taken
                self.wait_commands(grant)
                self.report(time_ns, self.step(action, time_ns))
        except Exception as err:  # serve raises it in the node's own thread
            with self.cond:
                self.failure = err
                self.cond.notify_all()
        self.heard = time.monotonic()
        self.busy = False  # no notify: a wake-up of serve's thread every step

    def serve(self, limit, silent):
        """A simulator's loop, until shutdown or an error of ``step`` (raised
        here). Each step runs in the thread that receives the grants: a
        hand-off to this one would cost every step a thread woken (tens of
        microseconds on a virtual machine). Meanwhile this
        thread sends the last report again every RESEND wall seconds
        without a grant (at once when a new owner appears) and calls
        ``silent()`` every ``limit`` s without one."""
        warn_at = time.monotonic() + limit
        while not rospy.is_shutdown():
            with self.cond:
                self.cond.wait_for(
                    lambda: self.rejoin or self.failure is not None, RESEND)
                if self.failure is not None:
                    raise self.failure
                rejoin, self.rejoin = self.rejoin, False
                now = time.monotonic()
                quiet = not self.busy and now - self.heard > RESEND
            if rejoin or quiet:
                self._send_again()
            if not quiet:
                warn_at = now + limit
            elif now > warn_at:
                warn_at = now + limit
                silent()
        deadline = time.monotonic() + LOST_COMMANDS
        while self.busy and time.monotonic() < deadline:  # a step under way ends
            rospy.rostime.wallsleep(0.01)                  # before the node does

    def simulators(self):
        """Names in the newest grant (every simulator is in each)."""
        with self.cond:
            return set(self.members)

    def connected(self):
        """True once the owner takes this node's reports and sends it grants."""
        return bool(self.pub.get_num_connections() and self.sub.get_num_connections())

    def join(self, wait):
        """Join the owner's lockstep, waiting up to ``wait`` wall seconds
        for it to be there; the first grant follows. Raises JoinError."""
        deadline = time.monotonic() + wait
        while not self.connected():  # a report sent before would be lost
            if time.monotonic() > deadline or rospy.is_shutdown():
                raise JoinError('nothing grants lockstep steps on %s after %.1f s: '
                                'is sim_clock running (sim_clock.launch)?'
                                % (GRANT_TOPIC, wait))
            rospy.rostime.wallsleep(0.01)
        with self.cond:
            self.grant = None
            self.heard = time.monotonic()
        if self.every_step and not self.own_time:
            self.own_time = keep_own_time()
        self.joined, self.left = True, False
        self.report(self.follower.handled or 0, 0)

    def wait_grant(self, limit=None):
        """Wait for the next step granted to this node; return (action,
        time ns, grant): action HANDLE or BACK (rbx1_nav.lockstep.Follower).
        Sends the last report again every RESEND wall seconds without a
        grant. None after ``limit`` wall seconds without one, or at shutdown.
        """
        started = time.monotonic()
        while not rospy.is_shutdown():
            with self.cond:
                self.cond.wait_for(lambda: self.grant is not None or self.rejoin,
                                   RESEND)
                grant, self.grant = self.grant, None
                self.rejoin = False
            if grant is None:
                if limit is not None and time.monotonic() - started > limit:
                    return None
                self._send_again()
                continue
            taken = self._take(grant)
            if taken:
                return taken
        return None

    def _take(self, grant):
        """(action, time ns, grant) of a grant to handle; None for one
        already handled (the report goes again) or stale (refused)."""
        time_ns = to_ns(grant.time)
        action = self.follower.grant(grant.session, time_ns)
        if action == REPEAT:
            self._send_again()
        elif action == STALE:
            rospy.logwarn('%s: lockstep grant at %.3f s is before the step '
                          'already handled (%.3f s): refused', self.name,
                          time_ns * 1e-9, self.follower.handled * 1e-9)
        else:
            if self.own_time:
                rospy.rostime._set_rostime(grant.time)
            return action, time_ns, grant
        return None

    def _send_again(self):
        with self.sending:
            if self.joined and self.last is not None:
                publish(self.pub, self.last)

    def wait_commands(self, grant):
        """A simulator, before stepping: wait (wall time) until every command
        counted in ``grant`` has arrived; after LOST_COMMANDS s take the rest
        as lost, with a warning."""
        counts = list(zip(grant.cmd_topics, grant.cmd_senders, grant.cmd_counts))
        deadline = time.monotonic() + LOST_COMMANDS
        with self.cond:
            if not self.settled:
                self.ledger.settle(counts)
                self.settled = True
            while self.ledger.missing(counts):
                if time.monotonic() > deadline:
                    for topic, name, short in self.ledger.give_up(counts):
                        rospy.logwarn('%s: %d cmd_vel message(s) from %s on %s lost '
                                      'on the way; going on without them',
                                      self.name, short, name, topic)
                elif rospy.is_shutdown():
                    return
                else:
                    self.cond.wait(0.05)

    def command_from(self, topic, msg):
        """A simulator: count a command that arrived on ``topic``."""
        with self.cond:
            self.ledger.arrived(topic, sender(msg))
            self.cond.notify_all()

    def sent(self, topic):
        """A motion node: count a command it published on ``topic``."""
        self.sent_counts[topic] = self.sent_counts.get(topic, 0) + 1

    def report(self, handled_ns, next_ns, leaving=False):
        """Handled ``handled_ns``; ``next_ns`` its next tick. After leave()
        (a shutdown hook, from another thread) none goes out, so a node on
        its way out cannot join again."""
        with self.sending:  # not interleaved with leave() from another thread
            if self.left:
                return
            self.follower.handled_step(handled_ns or None)
            topics = sorted(self.sent_counts)
            self.last = LockstepReport(
                handled=from_ns(handled_ns), next=from_ns(next_ns),
                every_step=self.every_step, leaving=leaving, cmd_topics=topics,
                cmd_counts=[self.sent_counts[t] for t in topics])
            publish(self.pub, self.last)

    def leave(self):
        """Leave the lockstep (a no-op when not a member): the last report
        carries the commands sent, so the simulator still waits for them."""
        with self.sending:
            if not self.joined:
                return
            self.report(self.follower.handled or 0, 0, leaving=True)
            self.joined, self.left = False, True
