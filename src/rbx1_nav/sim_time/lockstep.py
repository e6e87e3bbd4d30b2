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
* A **filter** (pose_ekf.py) is granted its own ticks too, and a **bag
  player** (lockstep_play.py) the stamps of its messages.

Every member reports how many messages it has published on each topic it
counts (commands, sensor messages, estimates), and each grant carries
those counts, so a member granted a step first waits until it has
received every message on its own inputs that the reports behind the
grant counted (messages travel on their own connections): a simulator its
commands, a filter its sensor messages. A member whose answer must not
depend on when a message arrives (a filter, a course following a
filter's transform) then takes only those counted messages, and keeps any
newer one for its next grant (rbx1_nav.sim_time.member.Inbox).
``/clock`` is published for ordinary nodes (RViz, rosbag, a user's
script); no member waits for it. Time jumps from event to event: the next grant is
the earliest next tick any member asked for, so a 20 Hz course on a 50 Hz
simulator costs the union of both grids, not a 10 ms walk. With ``batch``
(sim_clock at full speed, where nothing watches the wall clock) only the
motion nodes' ticks are granted while any takes part: a simulator steps
through its own grid up to each grant on its own, as Gazebo's physics runs
between two sensor or controller updates, with the same states and stamps
(its tf and ground truth at the grants only: rbx1_nav.sim.loop_ros) and a
third of the round trips.

Why nothing can wait forever (the deadlock argument):

1. The owner waits only for the reports of the members it granted. A
   member's handling of a grant waits only on messages already sent before
   the grant, or sent by another member handling the same grant without
   waiting for anyone: a simulator or a filter waits for messages counted
   in reports the owner has already received (sent before those reports); a motion
   node waits for the simulator's state at T, which the simulator publishes
   without waiting for any node at T. The wait-for relation within a step
   is node -> simulator -> earlier messages: it has no cycle.
2. Members wait only for a grant naming them, never for ``/clock`` or their
   own reading of it. Grants and reports are idempotent, named by their
   time: a member that hears nothing for RESEND seconds sends its last
   report again, and the owner re-sends an unanswered grant. A lost or
   late message costs a re-send, never a frozen graph.
3. Every wait ends when what it waits for is gone, never on a wall-time
   limit while it is there: a loaded machine makes a step take longer,
   never changes what a member sees. The owner drops a member whose
   connection closed (it died) and waits for a live one however slow,
   naming it every second, as Gazebo's lockstep waits for its slowest
   sensor. A member joins once the connections of its counted messages
   are up at both ends; then it waits for a counted message while its
   sender is connected (the message is on its way, in order; STALLED s
   is a backstop), and takes it as lost once the sender is gone
   (LOST_MESSAGES s unconnected, and no longer publishing or not
   answering); a motion node waits for its grant while
   the owner is connected, and takes the clock as gone after GRANT_LIMIT
   s without one (its tf watchdog ends the course when a simulator dies).

Joining: a member sends a report without having been granted anything; its
first grant is the owner's next step, whatever time it asked for (so a new
owner, started from further back, takes over members of an old one).
Leaving: a report marked leaving, or the member's connection closing.
Times are integer nanoseconds; no rospy here, so the rules are unit-tested
without a master (test/unit/test_lockstep.py). A member's side of the rules
(Follower, MessageLedger, Inbox) is rbx1_nav.sim_time.member, which
every node that keeps time uses; the owner is here.
"""
from rbx1_nav.sim_time.member import NO_TICK

__all__ = ['Owner']


class _Member(object):
    __slots__ = ('next', 'every_step', 'passive', 'granted')

    def __init__(self, every_step, passive):
        self.next = None          # next tick asked for; None: the next step
        self.every_step = every_step
        self.passive = passive
        self.granted = None       # the step it owes a report for


class Owner(object):
    """The owner's side: who takes part, when the next step is, who owes a
    report. ``start`` (ns) is the time already published; ``step`` (ns) the
    step taken when no member asks for a time."""

    def __init__(self, start=0, step=10000000, batch=False):
        self.now = start
        self.step = step
        self.batch = batch
        self.members = {}   # name -> _Member
        self.sent = {}  # (topic, sender) -> messages it published

    def report(self, report):
        """Take a report; return (change, warning): change is 'joined',
        'left' or None, warning a sentence or None."""
        for topic, count in report.sent.items():
            self.sent[(topic, report.name)] = count
        member = self.members.get(report.name)
        if report.leaving:
            return ('left' if self.members.pop(report.name, None) else None), None
        if member is None:
            self.members[report.name] = _Member(report.every_step, report.passive)
            return 'joined', None
        if member.granted is None or report.handled != member.granted:
            return None, None  # a report sent again, or one overtaken
        member.granted = None
        if report.next == NO_TICK:
            member.next = None  # no tick of its own: the next step
            return None, None
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
        """True while a member that is no simulator and not passive (a
        motion node, a bag player: not a filter) takes part."""
        return any(not (m.every_step or m.passive) for m in self.members.values())

    def grant(self, time, names):
        """The step ``time`` goes out to ``names``; return the names still
        members (one may have left meanwhile)."""
        if time <= self.now:
            raise ValueError('step %d ns is not after %d ns' % (time, self.now))
        self.now = time
        names = [name for name in names if name in self.members]
        for name in names:
            self.members[name].granted = time
        return names

    def simulators(self):
        """Names of the members granted every step (simulators)."""
        return sorted(name for name, m in self.members.items() if m.every_step)

    def owing(self):
        """Names of the members that owe a report for the step granted."""
        return sorted(name for name, m in self.members.items()
                      if m.granted is not None)

    def drop(self, name):
        """Forget ``name`` (dead); True if it was a member."""
        return self.members.pop(name, None) is not None

    def sent_counts(self):
        """[(topic, sender, count)] of every member's reported messages."""
        return [(topic, sender, count)
                for (topic, sender), count in sorted(self.sent.items())]
