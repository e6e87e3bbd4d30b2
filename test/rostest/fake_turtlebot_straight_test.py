#!/usr/bin/env python3
"""rostest: the fake TurtleBot drives straight, stops by itself, reports well.

Runs against launch/fake_turtlebot.launch (model, robot_state_publisher and
sim clock included) at the speed chosen by the .test file. One Twist of
~speed m/s is sent once; the node's watchdog (cmd_timeout, set to the drive
time in the .test file) stops the robot. That makes the drive time the
node's own business, free of the test's scheduling at any sim speed.
Tolerances come from <param>s.
"""
import math
import os
import sys
import unittest

import rospy
import rostest
import tf2_ros

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from fake_turtlebot_recorder import Recorder, motion_episode, planar, wait_for  # noqa: E402

PKG = 'rbx1_nav'
NODE = 'fake_turtlebot/'


class StraightLine(unittest.TestCase):
    """One drive, recorded in setUpClass; each test checks one outcome."""

    @classmethod
    def setUpClass(cls):
        rospy.init_node('fake_turtlebot_straight_test')
        cls.speed = rospy.get_param('~speed', 0.2)
        cls.tol = rospy.get_param('~distance_tolerance', 0.001)
        cls.timeout = rospy.get_param(NODE + 'cmd_timeout')
        cls.radius = rospy.get_param(NODE + 'wheel_radius')
        cls.tf_buffer = tf2_ros.Buffer()
        cls.tf_listener = tf2_ros.TransformListener(cls.tf_buffer)
        cls.rec = Recorder()
        assert wait_for(lambda: len(cls.rec.snapshot('odom')) > 5, 30.0, wall=True), 'no odom'
        cls.sent = cls.rec.send(cls.speed, 0.0)
        assert cls.rec.wait_stopped(cls.sent, 10 * cls.timeout + 60.0), 'robot never stopped'
        rospy.sleep(0.5)  # a few more messages while standing still
        cls.odom = [planar(m) for m in cls.rec.snapshot('odom')]
        # ground_truth is a stream of its own: at high sim speeds its
        # subscriber may lag the odom one; wait (wall time) until it has the
        # last odom stamp too.
        last = cls.odom[-1][0]
        for _ in range(500):
            if any(m.header.stamp.to_sec() >= last
                   for m in cls.rec.snapshot('truth')[-5:]):
                break
            rospy.rostime.wallsleep(0.01)
        cls.k, cls.j = motion_episode(cls.rec.snapshot('odom'), cls.sent)
        cls.gap_start = cls.odom[cls.k][0] - cls.odom[cls.k - 1][0]
        cls.gap_stop = cls.odom[cls.j][0] - cls.odom[cls.j - 1][0]

    def test_distance_is_speed_times_drive_time(self):
        expected = self.speed * self.timeout
        tol = self.tol + self.speed * max(self.gap_start, self.gap_stop)
        _, x, y, yaw, _, _ = self.odom[-1]
        self.assertAlmostEqual(x, expected, delta=tol)
        self.assertAlmostEqual(y, 0.0, delta=1e-9)
        self.assertAlmostEqual(yaw, 0.0, delta=1e-9)

    def test_watchdog_stops_within_timeout_plus_one_period(self):
        started, stopped = self.odom[self.k][0], self.odom[self.j][0]
        self.assertLessEqual(stopped - started, self.timeout + self.gap_stop + 1e-6)
        # A command applied within a step of arrival: at most two gaps early.
        self.assertGreater(stopped - started,
                           self.timeout - self.gap_start - self.gap_stop - 1e-6)
        after = self.odom[self.j:]
        self.assertTrue(all(r[4] == 0.0 and r[5] == 0.0 for r in after))
        self.assertTrue(all(r[1:4] == after[0][1:4] for r in after))

    def test_ground_truth_matches_ideal_odometry(self):
        odom_by_stamp = {r[0]: r for r in self.odom}
        truth = [m for m in self.rec.snapshot('truth')
                 if m.header.stamp.to_sec() in odom_by_stamp][-1]
        self.assertEqual(truth.header.frame_id, 'world')
        self.assertEqual(truth.child_frame_id, 'base_footprint')
        _, x, y, yaw, _, _ = planar(truth)
        odom = odom_by_stamp[truth.header.stamp.to_sec()]
        self.assertAlmostEqual(odom[1], self.odom[-1][1], delta=1e-12)  # stopped
        for a, b in zip((x, y, yaw), odom[1:4]):
            self.assertAlmostEqual(a, b, delta=1e-9)

    def test_tf_has_the_stamp_and_pose_of_its_odom_message(self):
        odom_by_stamp = {r[0]: r for r in self.odom}
        matched = 0
        for msg in self.rec.snapshot('tf'):
            for tf in msg.transforms:
                if (tf.header.frame_id, tf.child_frame_id) != ('odom', 'base_footprint'):
                    continue
                stamp = tf.header.stamp.to_sec()
                if not self.odom[0][0] <= stamp <= self.odom[-1][0]:
                    continue
                self.assertIn(stamp, odom_by_stamp, 'tf stamp without odom message')
                _, x, y, yaw, _, _ = odom_by_stamp[stamp]
                self.assertAlmostEqual(tf.transform.translation.x, x, delta=1e-12)
                self.assertAlmostEqual(tf.transform.translation.y, y, delta=1e-12)
                matched += 1
        self.assertGreater(matched, 10)  # a slow test node may miss some

    def test_joint_states_turn_the_wheels_by_the_distance(self):
        last = self.rec.snapshot('joints')[-1]
        self.assertEqual(list(last.name), ['left_wheel_joint', 'right_wheel_joint'])
        x = self.odom[-1][1]
        for angle in last.position:
            self.assertAlmostEqual(angle * self.radius, x, delta=1e-9)
        moving = [m for m in self.rec.snapshot('joints')
                  if self.odom[self.k][0] <= m.header.stamp.to_sec() < self.odom[self.j][0]]
        self.assertTrue(moving)
        for m in moving:
            for vel in m.velocity:
                self.assertAlmostEqual(vel * self.radius, self.speed, delta=1e-9)

    def test_covariances_are_non_zero(self):
        msg = self.rec.snapshot('odom')[-1]
        for cov in (msg.pose.covariance, msg.twist.covariance):
            self.assertTrue(all(cov[7 * i] > 0 for i in range(6)), cov)

    def test_robot_model_is_animated_in_tf(self):
        # robot_state_publisher is no lockstep member: its wheel transforms
        # may lag, so wait (a wall-clock deadline: at 20x, 5 simulated s
        # are a quarter of a wall second) for the wheel where the robot stopped.
        def wheel():
            try:
                return self.tf_buffer.lookup_transform('odom', 'left_wheel_link',
                                                       rospy.Time(0)).transform
            except tf2_ros.TransformException:
                return None

        def at_stop():
            tf = wheel()
            return tf is not None and abs(tf.translation.x - self.odom[-1][1]) <= 1e-6
        wait_for(at_stop, 30.0, wall=True)
        tf = wheel()
        self.assertIsNotNone(tf, 'no odom -> left_wheel_link on tf')
        self.assertAlmostEqual(tf.translation.x, self.odom[-1][1], delta=1e-6)
        self.assertAlmostEqual(tf.translation.y, 0.13, delta=1e-6)
        self.assertTrue(math.isfinite(tf.rotation.w))


if __name__ == '__main__':
    # One results file per .test (rostest names the test node after it).
    name = next((arg.split(':=', 1)[1] for arg in sys.argv
                 if arg.startswith('__name:=')), 'fake_turtlebot_straight')
    rostest.rosrun(PKG, name, StraightLine, sys.argv)
