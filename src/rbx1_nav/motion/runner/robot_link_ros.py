"""A course's link to the robot: the cmd_vel publisher, what was sent, and the robot's state
read at a tick. This is the plain one: messages are used as they come. When simulated time
steps with its nodes, sim_time's MemberLink answers the same questions and holds each message
for the tick that counts it, so a tick reads the same ones on every run."""
import rospy

__all__ = ['RobotLink']


class RobotLink(object):
    """A real robot's or free-running simulator's link."""

    #: True when the link counts the commands: none is on its way at a tick.
    counts_commands = False

    def publisher(self, topic, msg_class, headers=None):
        """The publisher of the robot's commands (without Nagle's delay), ``headers`` added to
        its connection header."""
        return rospy.Publisher(topic, msg_class, queue_size=5, tcp_nodelay=True, headers=headers)

    def sent(self, topic):
        """A command went out on ``topic``."""

    def takers(self, nodes):
        """Those of ``nodes`` connected to cmd_vel that drive the robot."""
        return nodes

    def not_taken(self, topic, nodes, wait):
        """Why ``nodes`` on ``topic`` take no commands after ``wait`` s (None: they do)."""
        return None

    def arrived(self, topic, msg, item):
        """``msg`` came on ``topic``: True if the link keeps ``item`` (what the course needs of
        it) for a later tick, False to use it now."""
        return False

    def take(self, topic, key):
        """The items kept for this tick on ``topic``, in ``key`` order."""
        return ()

    def looks(self, tf, deadline):
        """The start-up looks for the base frame (TfFollower.polls)."""
        return tf.polls(deadline)

    def reading(self, tf, now):
        """(pose, stamp) of the robot at the tick ``now``, or None."""
        return tf.lookup()
