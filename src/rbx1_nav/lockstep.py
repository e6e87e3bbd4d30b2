"""Lockstep simulated time: one owner grants every step.

Under free-running simulated time a node that falls behind the clock (a
busy CPU, a high ``sim_speed``) sees the robot move further between its
control ticks than it planned, so a course's result depends on the
scheduler. In lockstep, as in Gazebo's lockstep, Webots' ``robot_step``
loop or an FMI co-simulation master, one **owner** of simulated time
(sim_clock) moves it: it tells the members "advance to T" (a *grant*) and
waits until each has answered "handled T" (a *report*). Then it runs as
fast as the machine allows (or as ``sim_speed`` caps it), and a course ends
in the same pose at any speed and under any load.

The members:

* A **simulator** (fake_turtlebot.py, fake_fleet.py, any later one) is
  granted every step: at T it applies the commands that arrived, steps its
  model to T (through each step of its own grid on the way) and publishes
  the state at each before it reports.
* A **motion node** is granted only its own ticks: at T it reads the
  simulator's state stamped T, publishes its command and reports, with the
  number of ``cmd_vel`` messages it has sent on each topic so far.

Each grant carries those command counts, so a simulator granted a step
first waits until it has received every command that the reports behind
the grant counted (commands travel on their own connections). ``/clock``
is published for ordinary nodes (RViz, rosbag, pose_ekf, a user's script);
no member waits for it. Time jumps from event to event: the next grant is
the earliest next tick any member asked for, so a 20 Hz course on a 50 Hz
simulator costs the union of both grids, not a 10 ms walk. With ``batch``
(sim_clock at full speed, where nothing watches the wall clock) only the
motion nodes' ticks are granted while any takes part: a simulator steps
through its own grid up to each grant on its own, as Gazebo's physics runs
between two sensor or controller updates, with the same states and stamps
and a third of the round trips.

Why nothing can wait forever (the deadlock argument):

1. The owner waits only for the reports of the members it granted. A
   member's handling of a grant waits only on messages already sent before
   the grant, or sent by another member handling the same grant without
   waiting for anyone: the simulator waits for commands counted in reports
   the owner has already received (sent before those reports); a motion
   node waits for the simulator's state at T, which the simulator publishes
   without waiting for any node at T. The wait-for relation within a step
   is node -> simulator -> earlier messages: it has no cycle.
2. Members wait only for a grant naming them, never for ``/clock`` or their
   own reading of it. Grants and reports are idempotent, named by their
   time: a member that hears nothing for RESEND seconds sends its last
   report again, and the owner re-sends an unanswered grant. A lost or
   late message costs a re-send, never a frozen graph.
3. Every wait has a watchdog in wall time: the owner drops a member whose
   connection closed at once and a silent one after SILENT (it rejoins
   with its next report); a simulator goes on without commands lost on
   the way after LOST_COMMANDS; a motion node stops waiting for state that
   does not come (the simulator died) and its tf watchdog ends the course.

Joining: a member sends a report without having been granted anything; its
first grant is the owner's next step, whatever time it asked for (so a new
owner, started from further back, takes over members of an old one).
Leaving: a report marked leaving, or the member's connection closing.
Times are integer nanoseconds; no rospy here, so the rules are unit-tested
without a master (test/unit/test_lockstep.py).
"""
import collections

__all__ = ['Owner', 'Follower', 'CommandLedger', 'Report', 'RESEND', 'SILENT',
           'LOST_COMMANDS', 'HANDLE', 'REPEAT', 'BACK', 'STALE']

#: Wall seconds a member waits for a grant, or the owner for a report,
#: before sending its last message again.
RESEND = 0.5
#: Wall seconds a granted member may stay silent before the owner drops
#: it (it rejoins with its next report).
SILENT = 3.0
#: Wall seconds a simulator waits for counted commands before taking them
#: as lost on the way.
LOST_COMMANDS = 1.0

#: What a member does with a grant (Follower.grant).
HANDLE, REPEAT, BACK, STALE = 'handle', 'repeat', 'back', 'stale'

#: A member's report: ``handled`` (ns) the step it answers (None when it
#: joins), ``next`` (ns) its next tick, ``every_step`` True for a
#: simulator, ``commands`` a dict {cmd_vel topic: messages sent so far},
#: ``leaving`` True on its last report.
Report = collections.namedtuple(
    'Report', 'name handled next every_step commands leaving')


class _Member(object):
    __slots__ = ('next', 'every_step', 'granted', 'silent_since')

    def __init__(self, every_step):
        self.next = None          # next tick asked for; None: the next step
        self.every_step = every_step
        self.granted = None       # the step it owes a report for
        self.silent_since = None  # when that grant went out (wall s)


class Owner(object):
    """The owner's side: who takes part, when the next step is, who owes a
    report. ``start`` (ns) is the time already published; ``step`` (ns) the
    step taken when no member asks for a time. ``wall`` times are passed
    in, so the watchdogs are testable without sleeping."""

    def __init__(self, start=0, step=10000000, batch=False):
        self.now = start
        self.step = step
        self.batch = batch
        self.members = {}   # name -> _Member
        self.commands = {}  # (topic, sender) -> cmd_vel messages it sent

    def report(self, report):
        """Take a report; return (change, warning): change is 'joined',
        'left' or None, warning a sentence or None."""
        for topic, count in report.commands.items():
            self.commands[(topic, report.name)] = count
        member = self.members.get(report.name)
        if report.leaving:
            return ('left' if self.members.pop(report.name, None) else None), None
        if member is None:
            self.members[report.name] = _Member(report.every_step)
            return 'joined', None
        if member.granted is None or report.handled != member.granted:
            return None, None  # a report sent again, or one overtaken
        member.granted = member.silent_since = None
        if report.next <= report.handled:
            member.next = None
            return None, ('%s asked for its next tick at %.9f s, not after the '
                          'step it handled (%.9f s): refused; granted the next '
                          'step instead' % (report.name, report.next * 1e-9,
                                            report.handled * 1e-9))
        member.next = report.next
        return None, None

    def next_grant(self):
        """(time, names) of the next step and the members it is granted
        to, or None without members. Call once no report is owed."""
        if not self.members:
            return None
        asked = [m.next for m in self.members.values() if m.next is not None]
        if self.batch:  # simulators' grids only when no node asks
            asked = ([m.next for m in self.members.values()
                      if m.next is not None and not m.every_step] or asked)
        time = min(asked) if asked else self.now + self.step
        time = max(time, self.now + 1)
        names = sorted(name for name, m in self.members.items()
                       if m.every_step or m.next is None or m.next <= time)
        return time, names

    def drives(self):
        """True while a member that is no simulator (a motion node) takes part."""
        return any(not m.every_step for m in self.members.values())

    def grant(self, time, names, wall):
        """The step ``time`` goes out to ``names`` at wall time ``wall``;
        return the names still members (one may have left meanwhile)."""
        if time <= self.now:
            raise ValueError('step %d ns is not after %d ns' % (time, self.now))
        self.now = time
        names = [name for name in names if name in self.members]
        for name in names:
            member = self.members[name]
            member.granted, member.silent_since = time, wall
        return names

    def owing(self):
        """Names of the members that owe a report for the step granted."""
        return sorted(name for name, m in self.members.items()
                      if m.granted is not None)

    def silent(self, wall, limit=SILENT):
        """Names of the members that have owed a report for over ``limit``
        wall seconds."""
        return sorted(name for name, m in self.members.items()
                      if m.granted is not None and wall - m.silent_since > limit)

    def drop(self, name):
        """Forget ``name`` (dead or silent); True if it was a member."""
        return self.members.pop(name, None) is not None

    def command_counts(self):
        """[(topic, sender, count)] of every member's reported commands."""
        return [(topic, sender, count)
                for (topic, sender), count in sorted(self.commands.items())]


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


class CommandLedger(object):
    """A simulator's count of the commands it received, per cmd_vel topic
    and sender, against the counts the motion nodes reported."""

    def __init__(self, topics):
        self.topics = set(topics)
        self.received = collections.Counter()  # (topic, sender) -> messages
        self.lost = collections.Counter()      # given up as lost on the way

    def arrived(self, topic, sender):
        self.received[(topic, sender)] += 1

    def missing(self, counts):
        """[(topic, sender, how many)] of the commands reported in ``counts``
        ((topic, sender, count) triples) that have not arrived; other
        simulators' topics are not this one's business."""
        return [(topic, sender, count - have)
                for topic, sender, count in counts if topic in self.topics
                for have in [self.received[(topic, sender)] + self.lost[(topic, sender)]]
                if have < count]

    def settle(self, counts):
        """A simulator's first grant: the commands counted before it took
        part were sent to its predecessor (or before it listened); none of
        them is awaited."""
        for topic, sender, count in counts:
            if topic in self.topics:
                self.lost[(topic, sender)] = max(0, count - self.received[(topic, sender)])

    def give_up(self, counts):
        """Take the missing commands of ``counts`` as lost; return them."""
        missing = self.missing(counts)
        for topic, sender, short in missing:
            self.lost[(topic, sender)] += short
        return missing
