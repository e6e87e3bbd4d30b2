"""Test helper: record what a fake_turtlebot publishes and send it commands.

Imported by the test/rostest/fake_turtlebot_*_test.py rostest nodes (not a node
itself). All waiting is in ROS time, so the tests behave the same at any
simulation speed; the rostest time-limit is the wall-clock backstop.
"""
import threading
import time

import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, JointState
from tf2_msgs.msg import TFMessage

from rbx1_nav.transform_utils import quat_to_angle


def planar(msg):
    """(stamp seconds, x, y, yaw, v, w) of a nav_msgs/Odometry."""
    p = msg.pose.pose
    t = msg.twist.twist
    return (msg.header.stamp.to_sec(), p.position.x, p.position.y,
            quat_to_angle(p.orientation), t.linear.x, t.angular.z)


class Recorder:
    """Every odom, ground_truth, joint_states, imu_data and /tf message of
    one robot (topics relative to ``ns``), appended from subscriber threads."""

    def __init__(self, ns=''):
        prefix = ns.rstrip('/') + '/' if ns else ''
        self.lock = threading.Lock()
        self.odom, self.truth, self.joints, self.imu, self.tf = [], [], [], [], []
        big = 100000  # keep every message, even at high sim speeds
        rospy.Subscriber(prefix + 'odom', Odometry, self._keep, self.odom, queue_size=big)
        rospy.Subscriber(prefix + 'ground_truth', Odometry, self._keep, self.truth,
                         queue_size=big)
        rospy.Subscriber(prefix + 'joint_states', JointState, self._keep, self.joints,
                         queue_size=big)
        rospy.Subscriber(prefix + 'imu_data', Imu, self._keep, self.imu, queue_size=big)
        rospy.Subscriber('/tf', TFMessage, self._keep, self.tf, queue_size=big)
        self.cmd_pub = rospy.Publisher(prefix + 'cmd_vel', Twist, queue_size=10)

    def _keep(self, msg, store):
        with self.lock:
            store.append(msg)

    def snapshot(self, name):
        """A copy of one message list."""
        with self.lock:
            return list(getattr(self, name))

    def send(self, v, w):
        """Publish Twist(v, w) once the robot listens; return the ROS time (s)."""
        assert wait_for(lambda: self.cmd_pub.get_num_connections() > 0, 30.0, wall=True), \
            'nobody subscribes %s' % self.cmd_pub.resolved_name
        msg = Twist()
        msg.linear.x, msg.angular.z = v, w
        self.cmd_pub.publish(msg)
        return rospy.Time.now().to_sec()

    def wait_stopped(self, after, wall_limit):
        """Wait until the odometry moved after ``after`` s and then stopped;
        False after ``wall_limit`` wall s (a deadline: simulated time runs
        at the simulator's pace, not this node's)."""
        return wait_for(lambda: motion_episode(self.snapshot('odom'), after),
                        wall_limit, wall=True)


def wait_for(predicate, timeout, poll=0.02, wall=False):
    """Sleep until ``predicate()`` holds; False after ``timeout`` s of ROS
    time, or of wall time with ``wall`` (for waits on other processes,
    such as connections: simulated time may race meanwhile)."""
    now = time.monotonic if wall else (lambda: rospy.Time.now().to_sec())
    deadline = now() + timeout
    while not predicate():
        if rospy.is_shutdown() or now() > deadline:
            return False
        if wall:
            rospy.rostime.wallsleep(poll)
        else:
            rospy.sleep(poll)
    return True


def motion_episode(odom_msgs, after=0.0):
    """Indices (k, j) in ``odom_msgs``: first moving message after ``after`` s
    and the first message after it with zero twist; None if incomplete."""
    rows = [planar(m) for m in odom_msgs]
    k = next((i for i, r in enumerate(rows)
              if r[0] > after and (r[4] != 0.0 or r[5] != 0.0)), None)
    if k is None:
        return None
    j = next((i for i in range(k + 1, len(rows))
              if rows[i][4] == 0.0 and rows[i][5] == 0.0), None)
    return None if j is None else (k, j)
