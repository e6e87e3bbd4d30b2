"""Whether this graph keeps simulated time, and whether that time steps with its nodes
(lockstep): the one answer, read at start-up by every node that keeps time. Imports nothing of
sim_time: on a real robot it is all of simulated time a course loads."""
import rospy

__all__ = ['use_sim_time', 'lockstep']


def use_sim_time():
    """True when the graph runs on a simulated /clock (/use_sim_time)."""
    return bool(rospy.get_param('/use_sim_time', False))


def lockstep():
    """True under lockstep simulated time: /use_sim_time and /lockstep true (sim_clock.launch)."""
    return use_sim_time() and bool(rospy.get_param('/lockstep', False))
