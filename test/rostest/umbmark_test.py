#!/usr/bin/env python3
"""UMBmark end to end, and its refusal of bad measurements.

The robot is config/realistic.yaml (~robot_config) with linear_scale_error
1, the given ~encoder_noise, ~right_wheel_radius_error and
~angular_scale_error (the
fake robot's wheel base error: odometry turns that much too far). The
truths UMBmark must find:

    Ed = right_wheel_radius_error / left_wheel_radius_error
    Eb = angular_scale_error x 2 / (left + right wheel radius error)

(Eb as the wheel_separation_multiplier that, beside radius multipliers
that keep the mean radius, makes odometry's turns true: the mean wheel is
0.25 % large here, which the paper's method folds into Eb.)
"""
import os
import sys
import tempfile
import unittest

import rospy
import rostest
import yaml

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import CourseProcess, FakeRobot, RobotWatch  # noqa: E402


def umbmark(params, wall_limit=250.0):
    """Run umbmark.py with ``params``; return (exit status, output)."""
    node = CourseProcess(script='umbmark.py', params=params)
    try:
        return node.wait(wall_limit=wall_limit), node.output
    finally:
        node.cleanup()


def umbmark_before_after(test, settings, params, workdir):
    """UMBmark (``params``) on a fake robot with ``settings``, then again,
    one run each way (E_max,syst is all it is read for), with the
    multipliers it printed set on the robot. Asserts both runs exit 0 and
    the first finds a supported correction; returns (the first results, the
    second results, the second's output). The second's plot, of both, in
    ``workdir``."""
    watch = RobotWatch()
    robot = FakeRobot.restart(None, watch, settings)
    try:
        before_file = os.path.join(workdir, 'before.yaml')
        status, output = umbmark(dict(params, results=before_file, plot=''))
        test.assertEqual(status, 0, output)
        test.assertIn('the correction is supported', output)
        with open(before_file) as f:
            before = yaml.safe_load(f)
        factors = before['corrections']
        robot = FakeRobot.restart(robot, watch, dict(settings, **{
            name: factors[name] for name in (
                'left_wheel_radius_multiplier',
                'right_wheel_radius_multiplier',
                'wheel_separation_multiplier')}))
        after_file = os.path.join(workdir, 'after.yaml')
        status, output = umbmark(dict(params, runs=1, results=after_file,
                                      compare=before_file,
                                      plot=os.path.join(workdir, 'after.png')))
        test.assertEqual(status, 0, output)
        with open(after_file) as f:
            after = yaml.safe_load(f)
    finally:
        robot.close()
    return before, after, output


class UmbmarkTest(unittest.TestCase):

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix='umbmark_test_')

    def test_umbmark_finds_ed_and_eb_and_its_corrections_work(self):
        with open(rospy.get_param('~robot_config')) as f:
            settings = yaml.safe_load(f)
        left, right = 1.0, float(rospy.get_param('~right_wheel_radius_error'))
        separation = float(rospy.get_param('~angular_scale_error'))
        settings.update(linear_scale_error=1.0, angular_scale_error=separation,
                        left_wheel_radius_error=left,
                        right_wheel_radius_error=right,
                        encoder_noise=float(rospy.get_param('~encoder_noise')))
        true_ed, true_eb = right / left, separation * 2.0 / (left + right)
        before, after, output = umbmark_before_after(
            self, settings, dict(rospy.get_param('~umbmark_params')), self.dir)
        ed_off = abs(before['ed'] - true_ed) / true_ed
        eb_off = abs(before['eb'] - true_eb) / true_eb
        print('RESULT Ed %.5f (true %.5f, off %.3f %%), Eb %.5f (true %.5f, '
              'off %.3f %%; the wheel base alone: %.2f), E_max,syst before '
              '%.1f mm, after %.1f mm; plots in %s' % (
                  before['ed'], true_ed, 100 * ed_off, before['eb'], true_eb,
                  100 * eb_off, separation, 1000 * before['e_max_syst'],
                  1000 * after['e_max_syst'], self.dir))
        self.assertLess(ed_off, float(rospy.get_param('~ed_tolerance')))
        self.assertLess(eb_off, float(rospy.get_param('~eb_tolerance')))
        self.assertLess(after['e_max_syst'] * float(rospy.get_param('~improvement')),
                        before['e_max_syst'])
        self.assertIn('E_max,syst before', output)

    def check_refused(self, measurements, words):
        status, output = umbmark({'runs': 2, 'side': 1.0,
                                  'measurements': measurements,
                                  'results': os.path.join(self.dir, 'bad.yaml'),
                                  'plot': os.path.join(self.dir, 'bad.png')})
        self.assertEqual(status, 1, output)
        self.assertIn(words, output)
        self.assertNotIn('multiply', output)
        self.assertFalse(os.path.exists(os.path.join(self.dir, 'bad.yaml')))

    def test_a_list_of_the_wrong_length_is_refused(self):
        # The node's exit on bad measurements; each check's message (NaN,
        # an error larger than the square) is unit-tested: test_params.py
        # (pairs) and test_umbmark.py (check_errors).
        self.check_refused('[[0.01, 0.02], [0.0, 0.01], [0.02, 0.0]]',
                           '~measurements must be a list of 4 [x, y] pairs')


if __name__ == '__main__':
    rospy.init_node('umbmark_test')
    rostest.rosrun('rbx1_nav', 'umbmark_test', UmbmarkTest)
