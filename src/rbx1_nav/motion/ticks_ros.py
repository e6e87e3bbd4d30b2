"""The control loop's clock: when each tick comes, and what the robot's
state is at a tick.

:class:`Ticks` is a real robot's: a tick every 1/~rate s of ROS time
(rospy.Rate), and the robot's state at a tick is the newest transform tf
has. It is also simulated time's when the simulator runs free. The
runner asks for this object once, at start-up (:func:`course_ticks`), and
every piece that depends on when things happen asks it, never the
simulator: a simulated graph that steps with its nodes supplies a variant
of the same methods (rbx1_nav.sim_time.course_member_ros), imported only then.
"""
import rospy

from rbx1_nav.sim_time.stepping_ros import stepped_ticks


class Ticks(object):
    """A tick every 1/``rate`` s of ROS time."""

    #: The robot's commands are counted by the clock, so none is still
    #: on its way when a tick comes (rbx1_nav.motion.settle.delivered).
    counts_commands = False
    #: ROS time may stop under /use_sim_time: the runner watches it
    #: (rbx1_nav.motion.watchdogs_ros.ClockWatchdog).
    watch_clock = True

    def __init__(self, rate):
        self.rate = rate

    def ticks(self):
        """The control ticks (ROS times), until shutdown."""
        rate = rospy.Rate(self.rate)
        while not rospy.is_shutdown():
            yield rospy.Time.now()
            rate.sleep()

    def arrived(self, topic, msg, item):
        """A message the course reads (``item``, what it needs of it) came
        on ``topic``; True if the clock keeps it for the tick that counts
        it (:meth:`take`), False to use it now."""
        return False

    def take(self, topic, key):
        """The items kept for this tick on ``topic``, in ``key`` order."""
        return ()

    def publisher(self, topic, msg_class):
        """The publisher of the robot's commands (without Nagle's delay)."""
        return rospy.Publisher(topic, msg_class, queue_size=5, tcp_nodelay=True)

    def sent(self, topic):
        """A command went out on ``topic``."""

    def takers(self, nodes):
        """Those of ``nodes`` (connected to the command topic) that drive
        the robot: every one."""
        return nodes

    def not_taken(self, topic, nodes, wait):
        """Why ``nodes``, connected to ``topic``, do not take its commands
        after ``wait`` s (None: every connected node does)."""
        return None

    def looks(self, tf, deadline):
        """The start-up looks for the base frame: tf's answer every 1/20 s
        until ``deadline``."""
        return tf.polls(deadline)

    def reading(self, tf, now):
        """(pose, stamp) of the robot at the tick ``now``, or None: the
        newest transform."""
        return tf.lookup()

    def pause(self, seconds):
        """Wait ``seconds`` of ROS time between courses."""
        rospy.sleep(seconds)

    def leave(self):
        """The last course has ended."""


def course_ticks(rate, wait, timeout, stop, tf_topic, odom_topic):
    """The clock of a course node: :class:`Ticks` at ``rate`` Hz, or the
    simulator's stepped variant when the graph steps with its nodes (with
    ~tf_wait ``wait`` and ~tf_timeout ``timeout`` for its waits on the
    simulator, ``stop()`` to stop the robot, and the resolved /tf and
    odometry topics the course reads)."""
    return (stepped_ticks(rate, wait, timeout, stop, tf_topic, odom_topic)
            or Ticks(rate))
