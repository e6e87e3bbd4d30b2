"""The fixed-rate loop of a simulator node (nodes/fake_turtlebot.py,
nodes/fake_fleet.py): :func:`spin_simulator` steps the model on a grid of
ROS times and publishes each step through its robots' RobotTopics
(rbx1_nav.sim.topics_ros), under lockstep as a simulator member
(:func:`spin_lockstep`), otherwise on whatever ROS time does
(:func:`spin_on_ros_time`).
"""
import rospy

from rbx1_nav.sim.params import MAX_CATCH_UP, WARN_PERIOD
from rbx1_nav.common.ros_time import time_moved_back_text
from rbx1_nav.sim_time import member_ros as lockstep
from rbx1_nav.sim_time import switch_ros
from rbx1_nav.sim_time.member import BACK
from rbx1_nav.common.publish_ros import from_ns, to_ns
from rbx1_nav.common.cmd_vel_watch_ros import watch_publishers

__all__ = ['spin_simulator', 'spin_on_ros_time', 'spin_lockstep']


def spin_simulator(rate, step, robots, log_name):
    """Call ``step(stamp)`` on a fixed grid of ROS times, every 1/``rate``
    s, until shutdown: under lockstep as a simulator member (every step
    granted to it, its robots' commands counted), otherwise on whatever ROS
    time does. ``robots`` are the RobotTopics it steps; every PERIOD s of
    rbx1_nav.common.cmd_vel_watch_ros the master's graph tells them of
    other publishers on cmd_vel and tf."""
    def hear_other_tf(graph):
        for robot in robots:
            if robot.tf_watch:
                robot.tf_watch.follow(graph)
    watch_publishers(log_name, [robot.cmd_sub.resolved_name for robot in robots],
                     also=hear_other_tf)
    if switch_ros.lockstep():
        spin_lockstep(rate, step, robots, log_name)
    else:
        spin_on_ros_time(rate, step, log_name)


def _time_moved_back(log_name, err):
    rospy.logwarn('%s: %s', log_name,
                  time_moved_back_text(err.time, 'Restarting from the new time'))


def spin_on_ros_time(rate, step, log_name):
    """Call ``step(stamp)`` on a fixed grid of ROS times, every 1/``rate`` s.

    When the caller wakes late (a busy CPU at a high sim speed) it catches
    up step by step, so the published stream is the same at any speed; only
    after more than MAX_CATCH_UP s behind does it skip ahead in one (still
    exact) step. Returns at shutdown.
    """
    # Integer nanoseconds: rospy.Time arithmetic was a tenth of a robot's CPU at 1x.
    period = to_ns(rospy.Duration.from_sec(1.0 / rate))
    next_tick = None
    while not rospy.is_shutdown():
        now = to_ns(rospy.Time.now())
        if now == 0:  # sim time has not started yet
            next_tick = None
        elif next_tick is None or now < next_tick - period:  # start or reset
            next_tick = now
        else:
            if (now - next_tick) * 1e-9 > MAX_CATCH_UP:
                rospy.logwarn_throttle(WARN_PERIOD, '%s: %.2f s behind ROS time; '
                                       'skipping ahead' % (log_name, (now - next_tick) * 1e-9))
                next_tick = now
            while next_tick <= now:
                step(from_ns(next_tick))
                next_tick += period
        try:
            rospy.sleep((period if next_tick is None
                         else next_tick - to_ns(rospy.Time.now())) * 1e-9)
        except rospy.ROSTimeMovedBackwardsException as err:
            _time_moved_back(log_name, err)
            next_tick = None
        except rospy.ROSInterruptException:
            break


def spin_lockstep(rate, step, robots, log_name):
    """:func:`spin_on_ros_time` as a lockstep simulator (rbx1_nav.sim_time.lockstep).

    sim_clock grants it every step: the 1/``rate`` grid it asks for and
    every tick a motion node asks for (at full speed only the ticks: then
    it steps through its own grid up to each on its own). At each it waits
    for the commands the nodes reported sending, steps to that time and
    publishes the state there (so a node steers by the pose of its very
    tick), then reports (lockstep.Member.serve).
    A grant from before the last step (a new clock, from further back)
    starts the model again from there.
    """
    grid = _Grid(int(round(1e9 / rate)), step, robots, log_name)
    member = lockstep.Member(every_step=True, step=grid.step_to, hold=True,
                             inputs=[r.cmd_sub.resolved_name for r in robots])
    for robot in robots:
        robot.member = member
    rospy.on_shutdown(member.leave)
    member.join_patiently(log_name)
    member.serve(lockstep.NoOwnerWarning(log_name))


class _Grid(object):
    """A lockstep simulator's own grid of steps, every ``period`` ns."""

    def __init__(self, period, step, robots, log_name):
        self.period = period
        self.step = step
        self.robots = robots
        self.log_name = log_name
        self.next = None  # the grid's next step (ns); None: from the next grant
        self.last = None  # the last step taken (ns)

    def step_to(self, action, now, commands):
        """Queue the ``commands`` the grant counts ((robot, Twist) pairs:
        each from the step it was sent after, the last one taken), step
        through the grid up to the granted ``now`` (ns) and to ``now``
        itself; return the next step wanted."""
        for robot, msg in commands:
            robot.command(msg)
        if action == BACK:
            _time_moved_back(self.log_name, rospy.ROSTimeMovedBackwardsException(
                (self.last - now) * 1e-9))
            self.next = None
        while self.next is not None and self.next < now:  # its own steps on the way
            _step_at(self.next, self.step, self.robots, granted=False)
            self.next += self.period
        _step_at(now, self.step, self.robots)
        self.last = now
        if self.next is None or now >= self.next:
            # The grid runs from zero, not from when this simulator
            # started: every course meets the same steps (sim_time.lockstep).
            self.next = (now // self.period + 1) * self.period
        return self.next


def _step_at(time_ns, step, robots, granted=True):
    """Step to ``time_ns``; commands queued from now on count from there.

    A step on the way to a grant (at full speed sim_clock grants only the
    nodes' ticks; ``granted`` False) sends only the sensor messages nodes
    use at every step: odom (a filter counts each, a course's stall count
    reads each velocity), the gyro and GPS. Not tf, ground truth or joint
    states: a node is granted its ticks and reads them there, and a 20 Hz
    course on this 50 Hz grid would receive three of each per tick and
    use one."""
    for robot in robots:
        robot.step_time = time_ns * 1e-9
    step(from_ns(time_ns), granted)
