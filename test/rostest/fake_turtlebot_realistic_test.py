#!/usr/bin/env python3
"""rostest: realistic mode, three robots in namespaces on one sim clock.

Each robot drives straight, then turns in place. Its odometry must report
the true motion scaled by linear_scale_error * odom_linear_scale_correction
and angular_scale_error * odom_angular_scale_correction (read from each
node's parameters), so the corrections cancel the errors; its gyro
(imu_data) must follow the true rotation whatever the odometry error.
Noise-free robots are held to ~exact_tolerance, noisy ones (encoder_noise
> 0, e.g. config/realistic.yaml) to ~noisy_tolerance and ~gyro_tolerance.
"""
import os
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from fake_turtlebot_recorder import Recorder, planar, wait_for  # noqa: E402
from rbx1_nav.transform_utils import quat_to_angle

PKG = 'rbx1_nav'


def by_stamp(msgs):
    return {m.header.stamp.to_sec(): m for m in msgs}


class Realistic(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('fake_turtlebot_realistic_test')
        cls.robots = rospy.get_param('~robots')
        cls.exact = rospy.get_param('~exact_tolerance', 1e-6)
        cls.noisy = rospy.get_param('~noisy_tolerance', 0.02)
        cls.gyro_tol = rospy.get_param('~gyro_tolerance', 0.01)
        cls.rec = {ns: Recorder(ns) for ns in cls.robots}
        # deltas() pairs odom, truth and imu by stamp from before each
        # command, so all three streams must be flowing first.
        for ns, rec in cls.rec.items():
            assert wait_for(lambda: all(len(rec.snapshot(kind)) > 5
                                        for kind in ('odom', 'truth', 'imu')),
                            30.0, wall=True), '%s: odom, ground_truth or imu_data missing' % ns
        cls.phases = {}
        for phase, (v, w) in (('straight', (0.2, 0.0)), ('turn', (0.0, 1.0))):
            sent = {ns: rec.send(v, w) for ns, rec in cls.rec.items()}
            for ns, rec in cls.rec.items():
                assert rec.wait_stopped(sent[ns], 100.0), "%s did not stop" % ns
            rospy.sleep(0.2)
            cls.phases[phase] = {ns: cls.deltas(rec, sent[ns]) for ns, rec in cls.rec.items()}

    @staticmethod
    def deltas(rec, sent):
        """Change of (odom, truth, imu) x and yaw from before ``sent`` to now."""
        odom, truth = by_stamp(rec.snapshot('odom')), by_stamp(rec.snapshot('truth'))
        imu = by_stamp(rec.snapshot('imu'))
        common = sorted(set(odom) & set(truth) & set(imu))
        t0 = max(t for t in common if t <= sent)
        t1 = common[-1]
        result = {}
        for name, msgs in (('odom', odom), ('truth', truth)):
            (_, x0, _, yaw0, _, _), (_, x1, _, yaw1, _, _) = planar(msgs[t0]), planar(msgs[t1])
            result[name] = (x1 - x0, yaw1 - yaw0)
        result['imu'] = (None, quat_to_angle(imu[t1].orientation)
                         - quat_to_angle(imu[t0].orientation))
        turning = [t for t in common if t0 < t <= t1 and planar(truth[t])[5] != 0.0]
        result['rates'] = [(imu[t].angular_velocity.z, planar(truth[t])[5]) for t in turning]
        return result

    def node_param(self, ns, name, default=1.0):
        return rospy.get_param('%s/fake_turtlebot/%s' % (ns, name), default)

    def tolerance(self, ns):
        return self.noisy if self.node_param(ns, 'encoder_noise', 0.0) > 0 else self.exact

    def test_odometry_distance_is_scaled(self):
        for ns in self.robots:
            scale = (self.node_param(ns, 'linear_scale_error')
                     * self.node_param(ns, 'odom_linear_scale_correction'))
            d = self.phases['straight'][ns]
            self.assertGreater(d['truth'][0], 0.05, ns)
            self.assertAlmostEqual(d['odom'][0] / d['truth'][0], scale,
                                   delta=self.tolerance(ns), msg=ns)

    def test_odometry_rotation_is_scaled(self):
        for ns in self.robots:
            scale = (self.node_param(ns, 'angular_scale_error')
                     * self.node_param(ns, 'odom_angular_scale_correction'))
            d = self.phases['turn'][ns]
            self.assertGreater(d['truth'][1], 0.3, ns)
            self.assertAlmostEqual(d['odom'][1] / d['truth'][1], scale,
                                   delta=self.tolerance(ns), msg=ns)

    def test_gyro_follows_the_true_rotation(self):
        for ns in self.robots:
            d = self.phases['turn'][ns]
            noisy = self.node_param(ns, 'encoder_noise', 0.0) > 0
            self.assertAlmostEqual(d['imu'][1], d['truth'][1],
                                   delta=self.gyro_tol if noisy else 1e-9, msg=ns)
            if not noisy:
                self.assertTrue(d['rates'], ns)
                for measured, true in d['rates']:
                    self.assertAlmostEqual(measured, true, delta=1e-12, msg=ns)

    def test_imu_message_is_usable(self):
        for ns, rec in self.rec.items():
            imu = rec.snapshot('imu')[-1]
            self.assertEqual(imu.header.frame_id, ns + '/base_footprint')
            self.assertGreater(imu.orientation_covariance[8], 0.0)
            self.assertGreater(imu.angular_velocity_covariance[8], 0.0)
            self.assertEqual(imu.linear_acceleration_covariance[0], -1.0)


if __name__ == '__main__':
    rostest.rosrun(PKG, 'fake_turtlebot_realistic', Realistic, sys.argv)
