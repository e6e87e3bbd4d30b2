"""A course's clock and link to the robot, chosen once at start-up, above motion and sim_time.

Every course node hands :func:`course_clock` to motion's runner: lockstep's member
(rbx1_nav.sim_time.course_member_ros, imported only then) when the graph steps with its nodes,
else plain ROS-time ticks, with a watch on /clock under /use_sim_time. motion imports nothing of
sim_time, and a real robot's course loads no lockstep module.
"""
import functools

from rbx1_nav.motion.runner.clock_ros import RateClock
from rbx1_nav.motion.runner.robot_link_ros import RobotLink
from rbx1_nav.sim_time import switch_ros

__all__ = ['course_clock']


def course_clock(rate, wait, timeout, stop, tf_topic, odom_topic):
    """(clock, link) of a course at ``rate`` Hz, given ~tf_wait, ~tf_timeout, ``stop()`` (the
    robot's) and the resolved topics the course reads."""
    if switch_ros.lockstep():
        from rbx1_nav.sim_time.course_member_ros import member_clock
        return member_clock(rate, wait, timeout, stop, tf_topic, odom_topic)
    watch = None
    if switch_ros.use_sim_time():
        from rbx1_nav.sim_time.clock_watch_ros import watch_clock
        watch = functools.partial(watch_clock, wait=wait, timeout=timeout, stop=stop)
    return RateClock(rate, watch), RobotLink()
