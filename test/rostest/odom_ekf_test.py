#!/usr/bin/env python3
"""rostest for odom_ekf.launch: /robot_pose_ekf/odom_combined in, /odom_ekf out.

Checks the node is up and silent before any input (it must not block on a
first message), then the contents of the republished Odometry, the twist
estimate, and that a NaN pose is dropped without killing the node.
"""
import math
import threading
import unittest

import rosgraph
import rospy
import rostest
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry


def make_pose(stamp, x, y, yaw, frame='/odom'):
    msg = PoseWithCovarianceStamped()
    msg.header.stamp = stamp
    msg.header.frame_id = frame
    msg.pose.pose.position.x, msg.pose.pose.position.y = x, y
    msg.pose.pose.orientation.z = math.sin(yaw / 2.0)
    msg.pose.pose.orientation.w = math.cos(yaw / 2.0)
    msg.pose.covariance = [0.001 * (i + 1) for i in range(36)]
    return msg


class OdomEkfTest(unittest.TestCase):
    """Drives /robot_pose_ekf/odom_combined and reads /odom_ekf."""

    def setUp(self):
        self.timeout = float(rospy.get_param('~timeout', 10.0))
        self.tol = float(rospy.get_param('~twist_tolerance', 1e-6))
        self.received = []
        self.cond = threading.Condition()
        self.sub = rospy.Subscriber('/odom_ekf', Odometry, self.on_odom)
        self.pub = rospy.Publisher('/robot_pose_ekf/odom_combined', PoseWithCovarianceStamped,
                                   queue_size=10)

    def on_odom(self, msg):
        with self.cond:
            self.received.append(msg)
            self.cond.notify_all()

    def wait_for(self, count):
        deadline = rospy.Time.now() + rospy.Duration(self.timeout)
        with self.cond:
            while len(self.received) < count and rospy.Time.now() < deadline:
                self.cond.wait(0.1)
        self.assertGreaterEqual(len(self.received), count,
                                'no Odometry on /odom_ekf within %g s'
                                % self.timeout)
        return self.received[count - 1]

    def wait_connected(self):
        deadline = rospy.Time.now() + rospy.Duration(self.timeout)
        while rospy.Time.now() < deadline and (
                self.pub.get_num_connections() == 0
                or self.sub.get_num_connections() == 0):
            rospy.sleep(0.05)
        self.assertGreater(self.pub.get_num_connections(), 0)
        self.assertGreater(self.sub.get_num_connections(), 0)

    def test_republishes_without_blocking(self):
        # The node is registered and wired before it has seen any input...
        master = rosgraph.Master('/odom_ekf_test')
        deadline = rospy.Time.now() + rospy.Duration(self.timeout)
        publishers = subscribers = []
        while rospy.Time.now() < deadline:
            publishers, subscribers, _ = master.getSystemState()
            # The node registers its publisher, then its subscriber.
            if (['/odom_ekf', ['/odom_ekf']] in publishers and '/odom_ekf'
                    in dict(subscribers).get('/robot_pose_ekf/odom_combined', [])):
                break
            rospy.sleep(0.1)
        self.assertIn(['/odom_ekf', ['/odom_ekf']], publishers)
        self.assertIn('/odom_ekf', dict(subscribers).get('/robot_pose_ekf/odom_combined', []))
        self.wait_connected()
        # ...and publishes nothing until a pose arrives.
        rospy.sleep(rospy.get_param('~quiet_period', 1.0))
        self.assertEqual(self.received, [])

        t0 = rospy.Time(1000, 500)
        first = make_pose(t0, 1.0, 2.0, 0.5)
        self.pub.publish(first)
        odom = self.wait_for(1)
        self.assertEqual(odom.header.stamp, t0)
        self.assertEqual(odom.header.frame_id, 'odom')
        self.assertEqual(odom.child_frame_id, 'base_footprint')
        self.assertEqual(odom.pose.pose, first.pose.pose)
        self.assertEqual(list(odom.pose.covariance),
                         list(first.pose.covariance))
        self.assertEqual(odom.twist.twist.linear.x, 0.0)
        self.assertGreaterEqual(odom.twist.covariance[0], 1e3)

        self.pub.publish(make_pose(t0 + rospy.Duration(0.25), float('nan'),
                                   2.0, 0.5))
        # Forward 0.5 m along yaw 0.5 and turn 0.1 rad, in 0.5 s.
        second = make_pose(t0 + rospy.Duration(0.5),
                           1.0 + 0.5 * math.cos(0.55),
                           2.0 + 0.5 * math.sin(0.55), 0.6)
        rospy.sleep(0.2)
        self.pub.publish(second)
        odom = self.wait_for(2)
        self.assertEqual(odom.header.stamp, second.header.stamp,
                         'the NaN pose was republished')
        self.assertAlmostEqual(odom.twist.twist.linear.x, 1.0,
                               delta=self.tol)
        self.assertAlmostEqual(odom.twist.twist.linear.y, 0.0,
                               delta=self.tol)
        self.assertAlmostEqual(odom.twist.twist.angular.z, 0.2,
                               delta=self.tol)
        rospy.sleep(0.5)
        self.assertEqual(len(self.received), 2)


if __name__ == '__main__':
    rospy.init_node('odom_ekf_test')
    rostest.rosrun('rbx1_nav', 'odom_ekf', OdomEkfTest)
