#!/usr/bin/env python3
"""rostest: robot_pose_ekf's own GPS test, and the same answer whenever
pose_ekf starts (pose_ekf_husky_gps.test).

robot_pose_ekf's test (test_robot_pose_ekf_gps.cpp) takes the last
robot_pose_ekf/odom_combined stamped before 1368022016.0 and expects it at
(1.669542, -3.849846) within 0.1 m and its quaternion z, w at (-0.597720,
0.801634) within 0.005 (yaw -73.42 deg, about 0.7 deg); it also wants more
than 200 estimates spanning 32 to 52 s, the first within 2.5 s of the first
odometry. This node also relays the bag's /encoder, /imu_data and /gps to
each late-started pose_ekf (~late_starts: namespace -> seconds into the
bag) from that time on, and asserts their poses at the last stamp they all
published before the end time agree within 1 cm and 0.2 deg.
"""
import math
import subprocess
import threading
import time
import unittest

import rosgraph
import rospy
import rostest
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu

from rbx1_nav.transform_utils import quat_to_angle

TIME_END = 1368022016.0
EKF_DURATION = 40.0
EXPECTED = (1.669542, -3.849846)  # m
EXPECTED_QZ_QW = (-0.597720, 0.801634)
EPS_TRANS, EPS_ROT = 0.1, 0.005
AGREE_M, AGREE_DEG = 0.01, 0.2
TOPICS = ('encoder', 'imu_data', 'gps')
SUBSCRIBE_WALL_LIMIT = 60.0  # s for every node to subscribe


def wait_for_subscribers(wanted):
    """Wait (wall time) until every ``(topic, node)`` of ``wanted`` is
    registered with the master as subscribed."""
    master = rosgraph.Master(rospy.get_name())
    deadline = time.monotonic() + SUBSCRIBE_WALL_LIMIT
    while True:
        _, subscribers, _ = master.getSystemState()
        have = set((topic, node) for topic, nodes in subscribers
                   for node in nodes)
        missing = set(wanted) - have
        if not missing:
            return
        if time.monotonic() > deadline:
            raise AssertionError('not subscribed after %.0f s: %s' % (
                SUBSCRIBE_WALL_LIMIT, sorted(missing)))
        time.sleep(0.2)


class Estimates(object):
    """Every estimate on one topic, by stamp."""

    def __init__(self, topic):
        self.lock = threading.Lock()
        self.poses = {}  # stamp -> (x, y, yaw, qz, qw)
        rospy.Subscriber(topic, PoseWithCovarianceStamped, self.on_msg,
                         queue_size=1000)

    def on_msg(self, msg):
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        with self.lock:
            self.poses[msg.header.stamp.to_sec()] = (
                p.x, p.y, quat_to_angle(q), q.z, q.w)

    def stamps(self):
        with self.lock:
            return sorted(self.poses)


class LateStart(object):
    """Relays the bag's sensor topics into ``ns`` from ``delay`` s on."""

    def __init__(self, ns, delay):
        self.delay, self.first = delay, None
        for topic, msg_type in (('encoder', Odometry), ('imu_data', Imu),
                                ('gps', Odometry)):
            pub = rospy.Publisher('/%s/%s' % (ns, topic), msg_type,
                                  queue_size=100)
            rospy.Subscriber('/' + topic, msg_type, self.relay, pub,
                             queue_size=100)

    def relay(self, msg, pub):
        stamp = msg.header.stamp.to_sec()
        if self.first is None:
            self.first = stamp
        if stamp >= self.first + self.delay:
            pub.publish(msg)


class HuskyGpsTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.main = Estimates('/robot_pose_ekf/odom_combined')
        late = rospy.get_param('~late_starts')
        cls.late = {ns: Estimates('/%s/robot_pose_ekf/odom_combined' % ns)
                    for ns in late}
        cls.relays = [LateStart(ns, delay) for ns, delay in late.items()]
        cls.odom_begin = []
        rospy.Subscriber('/encoder', Odometry, cls.on_odom)
        # The bag plays once every pose_ekf (and this node) listens: on a
        # loaded machine a node can take seconds to start, and one that
        # starts late into the bag gives another answer.
        main = rospy.get_param('~ekf_node')
        wait_for_subscribers(
            [('/' + t, n) for t in TOPICS for n in (main, rospy.get_name())]
            + [('/%s/%s' % (ns, t), '/%s%s' % (ns, main))
               for ns in late for t in TOPICS])
        # (nothing started yet: no tearDownClass needed should that fail)
        cls.play = subprocess.Popen(
            ['rosbag', 'play', '-q', '--clock', '--hz', '100', '-d', '2',
             '-r', str(rospy.get_param('~rate')), rospy.get_param('~bag'),
             '--topics'] + ['/' + t for t in TOPICS])
        # The deadline counts from the bag's first /clock: before it, ROS
        # time is 0 and a deadline of 60 s has passed at the bag's 1st tick.
        while rospy.get_rostime().is_zero() and not rospy.is_shutdown():
            rospy.sleep(0.1)  # returns once /clock has started
        deadline = rospy.get_rostime() + rospy.Duration(60.0)
        cls.odom_end = 0.0
        while cls.odom_end < TIME_END + 1.0 and not rospy.is_shutdown():
            if rospy.get_rostime() > deadline:
                break
            rospy.sleep(0.1)

    @classmethod
    def tearDownClass(cls):
        cls.play.terminate()
        cls.play.wait()

    @classmethod
    def on_odom(cls, msg):
        stamp = msg.header.stamp.to_sec()
        if not cls.odom_begin:
            cls.odom_begin.append(stamp)
        cls.odom_end = stamp

    def test_robot_pose_ekf_gps_expectations(self):
        self.assertGreater(self.odom_end, TIME_END, 'the bag did not play')
        stamps = self.main.stamps()
        before = [s for s in stamps if s < TIME_END]
        self.assertTrue(before, 'no estimate from pose_ekf before %.1f'
                        % TIME_END)
        end = before[-1]
        x, y, yaw, qz, qw = self.main.poses[end]
        report = ('last estimate before %.1f: stamp %.3f, (%.3f, %.3f) m, '
                  'yaw %.2f deg; robot_pose_ekf expects (%.3f, %.3f), yaw '
                  '%.2f deg; %d estimates' % (
                      TIME_END, end, x, y, math.degrees(yaw), EXPECTED[0],
                      EXPECTED[1], math.degrees(2.0 * math.atan2(
                          EXPECTED_QZ_QW[0], EXPECTED_QZ_QW[1])),
                      len(stamps)))
        print(report, flush=True)
        duration = end - stamps[0]
        self.assertTrue(0.8 * EKF_DURATION < duration < 1.3 * EKF_DURATION,
                        'estimates span %.1f s' % duration)
        self.assertAlmostEqual(stamps[0], self.odom_begin[0], delta=2.5)
        self.assertAlmostEqual(end, TIME_END, delta=1.0)
        self.assertAlmostEqual(x, EXPECTED[0], delta=EPS_TRANS, msg=report)
        self.assertAlmostEqual(y, EXPECTED[1], delta=EPS_TRANS, msg=report)
        self.assertAlmostEqual(qz, EXPECTED_QZ_QW[0], delta=EPS_ROT,
                               msg=report)
        self.assertAlmostEqual(qw, EXPECTED_QZ_QW[1], delta=EPS_ROT,
                               msg=report)
        # robot_pose_ekf's filter times, read off the stamps: as many at
        # any playback speed.
        self.assertGreater(len(before), 200, report)

    def test_started_late_same_answer(self):
        common = set.intersection(*(
            set(s for s in est.stamps() if s < TIME_END)
            for est in self.late.values()))
        self.assertTrue(common, 'no stamp common to the late starters')
        end = max(common)
        poses = {ns: est.poses[end][:3] for ns, est in self.late.items()}
        text = 'at stamp %.3f: %s' % (end, '; '.join(
            '%s (%.4f, %.4f) m yaw %.3f deg' % (ns, p[0], p[1],
                                                math.degrees(p[2]))
            for ns, p in sorted(poses.items())))
        print(text, flush=True)
        first = poses[min(poses)]
        for pose in poses.values():
            self.assertLess(math.hypot(pose[0] - first[0],
                                       pose[1] - first[1]), AGREE_M, text)
            self.assertLess(abs(math.degrees(math.remainder(
                pose[2] - first[2], 2.0 * math.pi))), AGREE_DEG, text)


if __name__ == '__main__':
    rospy.init_node('pose_ekf_husky_gps_test')
    rostest.rosrun('rbx1_nav', 'pose_ekf_husky_gps', HuskyGpsTest)
