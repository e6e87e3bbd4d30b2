"""The control loop's clock: when each tick comes, and the robot's state at a tick. Every piece
that depends on when things happen asks it, never a simulator; a graph that steps with its nodes
supplies a variant with the same methods (rbx1_nav.sim_time.stepping_ros), imported only then."""
import rospy

from rbx1_nav.sim_time.stepping_ros import stepped_ticks, watch_clock


class Ticks(object):
    """A real robot's or free-running simulator's clock: ROS-time ticks 1/``rate`` s apart."""

    #: True when the clock counts the commands: none is on its way at a tick.
    counts_commands = False

    def __init__(self, rate, wait, timeout, stop):
        self.rate, self.wait, self.timeout, self.stop = rate, wait, timeout, stop

    def start(self, name):
        """Before node ``name``'s first course: under simulated time, the /clock watch."""
        watch_clock(name, self.wait, self.timeout, self.stop)

    def ticks(self):
        """The control ticks (ROS times), until shutdown."""
        rate = rospy.Rate(self.rate)
        while not rospy.is_shutdown():
            yield rospy.Time.now()
            rate.sleep()

    def arrived(self, topic, msg, item):
        """``msg`` came on ``topic``: True if the clock took ``item`` (what the course needs of
        it: the course is not to keep it), False to use it now."""
        return False

    def take(self, topic, key):
        """The items kept for this tick on ``topic``, in ``key`` order."""
        return ()

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

    def looks(self, tf, deadline):
        """The start-up looks for the base frame (TfFollower.polls)."""
        return tf.polls(deadline)

    def reading(self, tf, now):
        """(pose, stamp) of the robot at the tick ``now``, or None."""
        return tf.lookup()

    def pause(self, seconds):
        """Wait ``seconds`` of ROS time between courses."""
        rospy.sleep(seconds)

    def leave(self):
        """The last course has ended."""


def course_ticks(rate, wait, timeout, stop, tf_topic, odom_topic):
    """:class:`Ticks` at ``rate`` Hz, or the stepped variant when the graph steps with its nodes
    (given ~tf_wait, ~tf_timeout, ``stop()`` and the resolved topics the course reads)."""
    return (stepped_ticks(rate, wait, timeout, stop, tf_topic, odom_topic)
            or Ticks(rate, wait, timeout, stop))
