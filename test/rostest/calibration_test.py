#!/usr/bin/env python3
"""Calibration end to end: calibrate_linear.py and calibrate_angular.py
against the fake robot with known scale errors, then the corrections at work.

The robot is config/realistic.yaml (~robot_config: noise, latency,
acceleration limits, fixed seed) with ~linear_scale_error and
~angular_scale_error. Each calibration runs once with the simulator's
ground_truth as the tape measure; its printed correction must be within
~correction_tolerance (relative) of the true one, 1 / error. Then the
out-and-back course in precise mode runs on the uncorrected robot and on a
fresh robot with both corrections set; with them, the course must end
~improvement times closer to its start (ground truth).

A negative measurement given with dynparam (which exits 0 whatever the node
makes of it) is refused by the node with a warning naming the value, and
the field goes back to 0.
"""
import os
import subprocess
import sys
import unittest

import rospy
import rostest
import yaml

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import (WALL_LIMIT, CourseProcess, FakeRobot, RobotWatch,  # noqa: E402
                            calibrate, course_end_error, wait_until)
from rosrun import rosrun  # noqa: E402


class CalibrationTest(unittest.TestCase):

    def setUp(self):
        with open(rospy.get_param('~robot_config')) as f:
            self.settings = yaml.safe_load(f)
        self.errors = {'linear': float(rospy.get_param('~linear_scale_error')),
                       'angular': float(rospy.get_param('~angular_scale_error'))}
        self.settings.update(linear_scale_error=self.errors['linear'],
                             angular_scale_error=self.errors['angular'])
        self.watch = RobotWatch()
        self.robot = None

    def tearDown(self):
        if self.robot:
            self.robot.close()

    def start_robot(self, **corrections):
        self.robot = FakeRobot.restart(self.robot, self.watch,
                                       dict(self.settings, **corrections))

    def calibrate(self, kind):
        """Run calibrate_<kind>.py once; return the correction it prints."""
        value, output = calibrate(self, kind)
        truth = 1.0 / self.errors[kind]
        off = abs(value - truth) / truth
        print('RESULT %s correction %.4f, true %.4f, off by %.2f %%'
              % (kind, value, truth, 100 * off))
        self.assertLess(off, float(rospy.get_param('~correction_tolerance')),
                        output)
        return value

    def course_error(self):
        """Ground-truth (m, deg) from start to end of a precise course."""
        return course_end_error(self, self.watch, precise='true')

    def test_a_negative_measurement_is_refused_aloud(self):
        for kind, value in (('linear', '-1'), ('angular', '-352')):
            field = 'measured_distance' if kind == 'linear' else 'measured_angle'
            node = CourseProcess(script='calibrate_%s.py' % kind)
            try:
                wait_until(lambda: 'ready' in node.output or node.ended())
                self.assertIn('ready', node.output)
                name = node.node_name
                dynparam = subprocess.run(
                    rosrun('dynamic_reconfigure', 'dynparam', 'set', name,
                           field, value), stdout=subprocess.PIPE,
                    stderr=subprocess.STDOUT, universal_newlines=True, timeout=WALL_LIMIT)
                self.assertEqual(dynparam.returncode, 0, dynparam.stdout)
                line = '%s %s refused: ' % (field, float(value))
                wait_until(lambda: line in node.output or node.ended())
                self.assertIn(line, node.output)
                print('RESULT %s' % [l for l in node.lines if line in l][0])
                wait_until(lambda: rospy.get_param(name + '/' + field) == 0.0 or node.ended())
                self.assertEqual(rospy.get_param(name + '/' + field), 0.0,
                                 'the field was not set back to 0')
                self.assertNotIn('measured / odometry', node.output)
                node.interrupt()
                self.assertEqual(node.wait(), 0, node.output)
            finally:
                node.cleanup()

    def test_calibrations_find_the_scale_errors_and_fix_the_course(self):
        self.start_robot()
        linear = self.calibrate('linear')
        angular = self.calibrate('angular')
        before = self.course_error()
        self.start_robot(odom_linear_scale_correction=linear,
                         odom_angular_scale_correction=angular)
        after = self.course_error()
        print('RESULT out-and-back (precise) end error: uncorrected %.1f mm '
              '%.2f deg, corrected %.1f mm %.2f deg' % (
                  1000 * before[0], before[1], 1000 * after[0], after[1]))
        improvement = float(rospy.get_param('~improvement'))
        self.assertLess(after[0] * improvement, before[0])


if __name__ == '__main__':
    rospy.init_node('calibration_test')
    rostest.rosrun('rbx1_nav', 'calibration', CalibrationTest)
