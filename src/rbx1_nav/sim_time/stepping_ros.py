"""Whether this graph's simulated time steps with its nodes (lockstep),
and a course node's clock when it does.

Read once, at start-up, by every node that keeps time; on a real robot
this is all of simulated time a course loads.
"""
import rospy


def enabled():
    """True when this run uses lockstep simulated time: /use_sim_time and
    /lockstep both true (sim_clock.launch sets them)."""
    return bool(rospy.get_param('/use_sim_time', False)
                and rospy.get_param('/lockstep', False))


def stepped_ticks(rate, wait, timeout, stop, tf_topic, odom_topic):
    """Under lockstep, a course node's clock as a member
    (rbx1_nav.sim_time.course_member_ros.MemberTicks, imported only then);
    else None."""
    if not enabled():
        return None
    from rbx1_nav.sim_time.course_member_ros import MemberTicks
    return MemberTicks(rate, wait, timeout, stop, tf_topic, odom_topic)
