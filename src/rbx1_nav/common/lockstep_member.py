"""A lockstep member's rules: what a node taking part in lockstep
simulated time does with each grant, and how a simulator counts commands.

Every node that keeps time under lockstep takes part: the simulators, the
motion nodes, and any node later made a member, so a member's side of the
protocol is common ground; the owner of simulated time (sim_clock) and the
protocol's whole argument (why nothing can wait forever) are in
rbx1_nav.sim_time.lockstep. The ROS side of a member is
rbx1_nav.common.lockstep_member_ros. Times are integer nanoseconds; no
rospy here (test/unit/test_lockstep.py).
"""
import collections

__all__ = ['Follower', 'CommandLedger', 'Report', 'RESEND', 'SILENT',
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
