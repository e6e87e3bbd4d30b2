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

A measurement typed with dynparam while a test still drives (this test a
lockstep member holding simulated time mid-test, so it is typed then on
every run) is kept: when the test has ended the server's configuration
still holds it (start_test false), and the node prints the factor it makes
with the odometry of the test that just ended, which the test checks
against the one it computes from ground truth and the robot's known error:
typed / (true distance or angle x error), within ~correction_tolerance.
"""
import math
import os
import subprocess
import sys
import unittest

import rospy
import rostest
import yaml
from dynamic_reconfigure.encoding import decode_config
from dynamic_reconfigure.msg import Config

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import (CORRECTION, WALL_LIMIT, CourseProcess, FakeRobot,  # noqa: E402
                            RobotWatch, calibrate, course_end_error, wait_until)
from rosrun import rosrun  # noqa: E402
from rbx1_nav.common.publish_ros import to_ns  # noqa: E402
from rbx1_nav.sim_time import member_ros as lockstep  # noqa: E402
from rbx1_nav.sim_time.member import ALIGN, aligned  # noqa: E402

#: Each kind's early measurement case: a short test (its goal field and
#: value), how far under way (ground truth) the answer is typed, and the
#: answer, about the goal corrected by the robot's known error.
EARLY = {'linear': ('test_distance', 0.5, 0.1, '0.467'),
         'angular': ('test_angle', 90.0, 20.0, '96.8')}


class Updates(object):
    """Every configuration a reconfigure server publishes, decoded."""

    def __init__(self, node):
        self.configs = []
        self.sub = rospy.Subscriber(node + '/parameter_updates', Config,
                                    lambda msg: self.configs.append(decode_config(msg)))

    def after_test(self):
        """The first configuration with start_test false after one with it
        true (one update clears it when a test ends), or None."""
        started = False
        for config in list(self.configs):
            started = started or config['start_test']
            if started and not config['start_test']:
                return config
        return None


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

    def test_b_a_measurement_typed_while_the_test_drives_is_used(self):
        self.start_robot()
        for kind in ('linear', 'angular'):
            self.check_early_measurement(kind)

    def check_early_measurement(self, kind):
        goal, goal_value, under_way, typed = EARLY[kind]
        field = 'measured_distance' if kind == 'linear' else 'measured_angle'
        self.assertTrue(wait_until(self.watch.still), 'the robot moves before the test')
        start = self.watch.pose()

        def travel():  # ground truth since start, in the kind's unit (m, deg)
            now = self.watch.pose()
            if kind == 'linear':
                return math.hypot(now.x - start.x, now.y - start.y)
            return math.degrees(abs(math.remainder(now.yaw - start.yaw, 2 * math.pi)))

        member = lockstep.Member()
        rospy.on_shutdown(member.leave)
        member.join(30.0)  # first: time waits for this test from the node's start
        name = '/calibrate_%s' % kind
        updates = Updates(name)
        node = CourseProcess(script='calibrate_%s.py' % kind, params={
            'start_test': 'true', goal: goal_value, 'tf_timeout': 5.0})
        try:
            # Time moves only as this test reports its ticks: it stops at
            # the first tick (0.1 s) with the robot under way.
            for _, tick, _ in member.grants(rospy.get_name()):
                if tick % ALIGN == 0:
                    self.assertTrue(wait_until(lambda: to_ns(
                        self.watch.truth.header.stamp) >= tick or node.ended()),
                        'no ground truth at the tick')
                    if node.ended() or travel() > under_way:
                        break
                member.report(tick, aligned(tick + 1))
            self.assertFalse(node.ended(), node.output)
            typed_at = travel()
            dynparam = subprocess.run(
                rosrun('dynamic_reconfigure', 'dynparam', 'set', name, field, typed),
                stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                universal_newlines=True, timeout=WALL_LIMIT)
            self.assertEqual(dynparam.returncode, 0, dynparam.stdout)
            self.assertTrue(updates.configs and updates.configs[-1]['start_test'],
                            'the test was not running when the value was typed: %s'
                            % updates.configs[-1:])
            member.leave()
            self.assertTrue(wait_until(lambda: updates.after_test() or node.ended()),
                            'the test did not end')
            ended = updates.after_test()
            self.assertIsNotNone(ended, node.output)
            print('RESULT %s: %s %s typed %.3f %s under way (ground truth); configuration '
                  'after the test: start_test %s, %s %s' % (
                      kind, field, typed, typed_at, 'm' if kind == 'linear' else 'deg',
                      ended['start_test'], field, ended[field]))
            self.assertEqual(ended[field], float(typed),
                             'the value typed during the test was dropped when it ended:\n'
                             + node.output)
            self.assertEqual(rospy.get_param(name + '/' + field), float(typed))
            found = []
            wait_until(lambda: found.extend(CORRECTION.findall(node.output))
                       or found or node.ended())
            self.assertTrue(wait_until(self.watch.still), 'the robot still moves')
            truth = travel()
            node.interrupt()
            self.assertEqual(node.wait(), 0, node.output)
        finally:
            member.leave()
            node.cleanup()
        self.assertTrue(found, 'no correction printed:\n' + node.output)
        value = float(found[0][1])
        expected = float(typed) / (truth * self.errors[kind])
        off = abs(value - expected) / expected
        print('RESULT %s: printed factor %.4f; typed / (true %.4f x error %.2f) = %.4f, '
              'off by %.2f %%' % (kind, value, truth, self.errors[kind], expected, 100 * off))
        self.assertLess(off, float(rospy.get_param('~correction_tolerance')), node.output)

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
