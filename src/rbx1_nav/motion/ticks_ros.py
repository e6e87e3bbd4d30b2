"""The control loop's ticks: free running at ~rate, or granted by lockstep.

On a real robot (or simulated time without lockstep) a tick comes every
1/~rate s of ROS time (rospy.Rate). Under lockstep simulated time
(rbx1_nav.common.lockstep_member_ros) the node is a member from its
wait for the transform to the end of its course: it joins the owner of
simulated time, waits for each grant naming
it (the simulator has published its state at that tick), handles the tick,
and reports it handled with its next tick 1/~rate s on; time waits for it.
Its first tick is the first multiple of 0.1 s of simulated time
(rbx1_nav.common.lockstep_member.ALIGN) after the step it joined at, so it
meets the simulator's steps at the same offsets and ends the same whenever
it started.
A node that drives several courses in a row (UMBmark's runs) may stay a
member between them: time then waits for it between courses too, so each
course starts at the same simulated time on every run.
"""
import rospy

from rbx1_nav.common import lockstep_member_ros as lockstep
from rbx1_nav.common.lockstep_member import BACK, aligned
from rbx1_nav.common.publish_ros import from_ns
from rbx1_nav.motion.aborted import CourseAborted


class Ticks(object):
    """The ticks at ``rate`` Hz. Under lockstep ``member`` is the node's
    rbx1_nav.common.lockstep_member_ros.Member (else None); before the
    join, the wait for its inputs' connections and the join itself each
    wait up to ``join_wait`` wall s; a grant is waited for as long as the
    owner is connected, and up to max(GRANT_LIMIT, ``grant_wait``) wall s
    after the last tick once it is not; ``stop()`` stops the robot when
    the owner is gone."""

    def __init__(self, rate, member, join_wait, grant_wait, stop):
        self.rate = rate
        self.member = member
        self.join_wait = join_wait
        self.grant_wait = grant_wait
        self.stop = stop
        self.grant = None  # the lockstep grant of the current tick
        self.unreported = None  # a tick handed out and not reported (ns)

    def ticks(self, joined=lambda: None):
        """The control ticks (ROS times). Under lockstep ``joined()`` runs
        once this node is a member, before the first grant; the caller
        ends the membership with :meth:`leave`."""
        if self.member is None:
            rate = rospy.Rate(self.rate)
            while not rospy.is_shutdown():
                yield rospy.Time.now()
                rate.sleep()
            return
        member = self.member
        period = int(round(1e9 / self.rate))
        limit = max(lockstep.GRANT_LIMIT, self.grant_wait)
        wait = limit
        joining = False  # the next grant is a new membership's first
        first = None  # the first tick of a new membership (ns)
        if self.unreported is not None:  # still a member: the next tick
            member.report(self.unreported, self.unreported + period)
            self.unreported = None
        else:
            # The first grant may wait for the other members sim_clock's
            # ~members counts: up to the start-up wait (~tf_wait).
            wait = max(limit, self.join_wait)
            member.wait_for_inputs(self.join_wait, member.name)
            try:
                member.join(self.join_wait)
            except lockstep.JoinError as err:
                raise CourseAborted('/lockstep is set but this node cannot join: %s. '
                                    'Start the simulator with lockstep too, or set '
                                    '/lockstep false' % err)
            joined()
            joining = True
        while True:
            granted = member.wait_grant(wait)
            if granted is None:
                if rospy.is_shutdown():
                    return
                self.stop()
                raise CourseAborted(
                    '/clock has not advanced: nothing has granted lockstep steps on '
                    '%s for %.1f s of wall time (sim_clock gone); stopped the robot'
                    % (lockstep.GRANT_TOPIC, wait))
            wait = limit
            action, tick, grant = granted
            self.grant = grant
            if action == BACK:
                raise rospy.ROSTimeMovedBackwardsException(
                    (member.follower.handled - tick) * 1e-9)
            if joining:
                # The join grant is not a tick. From it on, every message a
                # grant counts on this node's inputs is awaited
                # (MessageLedger.settle); one sent just before the join may
                # have come or not, so the first tick comes after it: a
                # course then finds its robot and starts at the same tick
                # on every run.
                member.wait_counted(grant)
                first, joining = aligned(tick + 1), False
            if first is not None and tick < first:
                member.report(tick, first)  # not a tick of this node's
                continue
            first = None
            self.unreported = tick
            yield from_ns(tick)
            self.unreported = None
            member.report(tick, tick + period)

    def pause(self, seconds):
        """Wait ``seconds`` of ROS time: as granted ticks while a member
        between courses (time waits for this node), else rospy.sleep."""
        if self.unreported is None:
            rospy.sleep(seconds)
            return
        end = None
        for now in self.ticks():
            if end is None:
                end = now + rospy.Duration.from_sec(seconds)
            if now >= end:
                return

    def leave(self):
        """Leave the lockstep after a course (a no-op off lockstep)."""
        self.unreported = None
        if self.member is not None:
            self.member.leave()
