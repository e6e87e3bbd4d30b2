#!/usr/bin/env python3
"""rostest: robot_pose_ekf's own GPS test, and the same answer whenever
pose_ekf starts (pose_ekf_husky_gps.test).

robot_pose_ekf's test (test_robot_pose_ekf_gps.cpp) takes the last
robot_pose_ekf/odom_combined stamped before 1368022016.0 and expects it at
(1.669542, -3.849846) within 0.1 m and its quaternion z, w at (-0.597720,
0.801634) within 0.005 (yaw -73.42 deg, about 0.7 deg); it also wants more
than 200 estimates spanning 32 to 52 s, the first within 2.5 s of the first
odometry. Each late-started pose_ekf (~late_starts: namespace -> seconds
into the bag; ~gps_frame_rotation) gets the bag's /encoder, /imu_data and
/gps from that time on, from its own player; its pose at the last stamp
it published before the end time must agree within 1 cm and 0.2 deg with
the same filter's replaying the whole bag without ROS
(bench/accuracy/pose_ekf_husky.py, as test/unit/test_pose_ekf_husky.py does for
starts 0, 1.5 and 3 s into it).

The bag plays in lockstep (lockstep_play.py, one player per pose_ekf,
started here once every pose_ekf and this node listen): each pose_ekf
reads exactly the messages recorded up to each of its ticks, so the
estimates are the same on every run, however busy the machine.
"""
import math
import os
import subprocess
import sys
import threading
import time
import unittest

import rosbag
import rosgraph
import rospy
import rostest
from geometry_msgs.msg import PoseWithCovarianceStamped

from rbx1_nav.estimation.fusion import GyroOdomFusion
from rbx1_nav.transform_utils import quat_to_angle

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from rosrun import rosrun  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'bench', 'accuracy'))
import pose_ekf_husky as husky  # noqa: E402

TIME_END = 1368022016.0
EKF_DURATION = 40.0
EXPECTED = (1.669542, -3.849846)  # m
EXPECTED_QZ_QW = (-0.597720, 0.801634)
EPS_TRANS, EPS_ROT = 0.1, 0.005
AGREE_M, AGREE_DEG = 0.01, 0.2
TOPICS = ('encoder', 'imu_data', 'gps')
#: Wall seconds for every node to subscribe, and for the whole replay
#: (about 3 s at full speed on an idle 2-core machine): hang guards, never
#: verdicts on a loaded machine.
SUBSCRIBE_WALL_LIMIT = REPLAY_WALL_LIMIT = 300.0


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
        # No queue limit: every estimate counts, and at full speed they
        # come faster than a busy machine may run this callback.
        self.sub = rospy.Subscriber(topic, PoseWithCovarianceStamped, self.on_msg,
                                    queue_size=None)

    def on_msg(self, msg):
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        with self.lock:
            self.poses[msg.header.stamp.to_sec()] = (
                p.x, p.y, quat_to_angle(q), q.z, q.w)

    def stamps(self):
        with self.lock:
            return sorted(self.poses)

    def last(self):
        with self.lock:
            return max(self.poses) if self.poses else 0.0


def player(bag, ns, start):
    """lockstep_play.py playing the bag's sensor topics into ``ns`` from
    ``start`` s into the bag."""
    return subprocess.Popen(
        rosrun('rbx1_nav', 'lockstep_play.py', '__ns:=' + ns,
               '__name:=play_bag', '_bag:=' + bag, '_start:=%r' % start,
               '_topics:=' + ' '.join(TOPICS)))


class HuskyGpsTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        bag = rospy.get_param('~bag')
        # The independent record of the odometry: the bag itself.
        with rosbag.Bag(bag) as recorded:
            stamps = [m.header.stamp.to_sec() for _, m, _ in
                      recorded.read_messages(topics=['/encoder'])]
        cls.odom_begin = stamps[0]
        main = rospy.get_param('~ekf_node')
        starts = dict(rospy.get_param('~late_starts'), **{'/': 0.0})
        cls.main = Estimates('%s/odom_combined' % main)
        cls.late = {ns: Estimates('/%s%s/odom_combined' % (ns, main))
                    for ns in starts if ns != '/'}
        # The bag plays once every pose_ekf listens, and this node listens
        # to each of them: one that misses the start gives another answer.
        wait_for_subscribers([('/' + t, main) for t in TOPICS]
                             + [('/%s/%s' % (ns, t), '/%s%s' % (ns, main))
                                for ns in cls.late for t in TOPICS])
        deadline = time.monotonic() + SUBSCRIBE_WALL_LIMIT
        while not all(e.sub.get_num_connections()
                      for e in [cls.main] + list(cls.late.values())):
            if time.monotonic() > deadline:
                raise AssertionError('not connected to every pose_ekf')
            time.sleep(0.05)
        cls.players = [player(bag, ns, start) for ns, start in sorted(starts.items())]
        deadline = time.monotonic() + REPLAY_WALL_LIMIT
        while not rospy.is_shutdown() and time.monotonic() < deadline:
            if all(e.last() > TIME_END for e in [cls.main] + list(cls.late.values())):
                break
            time.sleep(0.1)

    @classmethod
    def tearDownClass(cls):
        for play in cls.players:
            play.terminate()
            play.wait()

    def test_robot_pose_ekf_gps_expectations(self):
        stamps = self.main.stamps()
        before = [s for s in stamps if s < TIME_END]
        self.assertTrue(before, 'no estimate from pose_ekf before %.1f'
                        % TIME_END)
        end = before[-1]
        x, y, yaw, qz, qw = self.main.poses[end]
        report = ('last estimate before %.1f: stamp %.3f, (%.3f, %.3f) m, '
                  'yaw %.2f deg; robot_pose_ekf expects (%.3f, %.3f), yaw '
                  '%.2f deg; %d estimates before it' % (
                      TIME_END, end, x, y, math.degrees(yaw), EXPECTED[0],
                      EXPECTED[1], math.degrees(2.0 * math.atan2(
                          EXPECTED_QZ_QW[0], EXPECTED_QZ_QW[1])),
                      len(before)))
        print(report, flush=True)
        duration = end - stamps[0]
        self.assertTrue(0.8 * EKF_DURATION < duration < 1.3 * EKF_DURATION,
                        'estimates span %.1f s' % duration)
        self.assertAlmostEqual(stamps[0], self.odom_begin, delta=2.5)
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

    def test_started_late_same_answer_as_without_ros(self):
        offline = husky.replay(
            GyroOdomFusion(gps_used=True, **husky.MODES['gps_frame_rotation']),
            husky.read_bag(rospy.get_param('~bag')))
        offline = {round(stamp, 6): pose for stamp, pose, _ in offline}
        for ns, estimates in sorted(self.late.items()):
            common = [s for s in estimates.stamps()
                      if s < TIME_END and round(s, 6) in offline]
            self.assertTrue(common, '%s: no stamp in common with the replay' % ns)
            end = common[-1]
            pose, replayed = estimates.poses[end][:3], offline[round(end, 6)]
            text = ('%s at stamp %.3f: (%.4f, %.4f) m yaw %.3f deg; without ROS from '
                    'the start (%.4f, %.4f) m yaw %.3f deg' % (
                        ns, end, pose[0], pose[1], math.degrees(pose[2]),
                        replayed[0], replayed[1], math.degrees(replayed[2])))
            print(text, flush=True)
            self.assertLess(math.hypot(pose[0] - replayed[0], pose[1] - replayed[1]),
                            AGREE_M, text)
            self.assertLess(abs(math.degrees(math.remainder(
                pose[2] - replayed[2], 2.0 * math.pi))), AGREE_DEG, text)

if __name__ == '__main__':
    rospy.init_node('pose_ekf_husky_gps_test')
    rostest.rosrun('rbx1_nav', 'pose_ekf_husky_gps', HuskyGpsTest)
