"""Whether this graph's simulated time steps with its nodes (lockstep), and a course node's clock
when it does; a course's watch on /clock. Read once, at start-up, by every node that keeps time;
on a real robot this is all of simulated time a course loads.
"""
import rospy


def enabled():
    """True under lockstep simulated time: /use_sim_time and /lockstep true (sim_clock.launch)."""
    return bool(rospy.get_param('/use_sim_time', False) and rospy.get_param('/lockstep', False))


def stepped_ticks(rate, wait, timeout, stop, tf_topic, odom_topic):
    """Under lockstep, a course node's clock as a member (imported only then); else None."""
    if not enabled():
        return None
    from rbx1_nav.sim_time.course_member_ros import MemberTicks
    return MemberTicks(rate, wait, timeout, stop, tf_topic, odom_topic)


def watch_clock(name, wait, timeout, stop):
    """Under /use_sim_time, for a course ticking on ROS time: wait up to ``wait`` s for the first
    /clock (CourseAborted if none), then stop the robot (``stop()``) and the node if it stands
    still for max(2 s, ``timeout``) (sim_time.clock_watch_ros). Nothing on a real robot."""
    if rospy.get_param('/use_sim_time', False):
        from rbx1_nav.sim_time.clock_watch_ros import ClockWatchdog, require_clock
        require_clock(wait)
        ClockWatchdog(name, timeout, stop).start()
