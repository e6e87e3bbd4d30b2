"""A course's clock: when each control tick comes. The runner is handed one (chosen above
motion, in rbx1_nav.entry.course_clock_ros); this is the plain one, for a real robot or a
free-running simulator. When simulated time steps with its nodes, sim_time's MemberClock
answers the same questions."""
import rospy

__all__ = ['RateClock']


class RateClock(object):
    """ROS-time ticks 1/``rate`` s apart; ``watch(name)``, when given, runs before node
    ``name``'s first course (under /use_sim_time: the watch on /clock)."""

    def __init__(self, rate, watch=None):
        self.rate, self.watch = rate, watch

    def start(self, name):
        """Before node ``name``'s first course."""
        if self.watch is not None:
            self.watch(name)

    def ticks(self):
        """The control ticks (ROS times), until shutdown."""
        rate = rospy.Rate(self.rate)
        while not rospy.is_shutdown():
            yield rospy.Time.now()
            rate.sleep()

    def pause(self, seconds):
        """Wait ``seconds`` of ROS time between courses."""
        rospy.sleep(seconds)

    def leave(self):
        """The last course has ended."""
