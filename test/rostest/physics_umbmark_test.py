#!/usr/bin/env python3
"""UMBmark on the TurtleBot with real dynamics (fake_turtlebot.py with
~physics, carpet, fixed seed) whose right wheel is ~right_wheel_radius_error
of the nominal radius and whose wheels are ~wheel_separation_error of the
nominal separation apart: the multipliers UMBmark prints, set on the
robot, bring E_max,syst down at least ~improvement times (both
benchmarks measured with ground_truth).
"""
import tempfile
import unittest

import rospy
import rostest

from umbmark_test import umbmark_before_after


class PhysicsUmbmarkTest(unittest.TestCase):

    def test_umbmark_correction_works_on_the_physics_robot(self):
        settings = {'physics': True, 'floor': 'carpet', 'seed': 1,
                    'right_wheel_radius_error': float(
                        rospy.get_param('~right_wheel_radius_error')),
                    'wheel_separation_error': float(
                        rospy.get_param('~wheel_separation_error'))}
        workdir = tempfile.mkdtemp(prefix='physics_umbmark_')
        before, after, _ = umbmark_before_after(
            self, settings, dict(rospy.get_param('~umbmark_params')), workdir)
        print('RESULT physics UMBmark: Ed %.5f, Eb %.5f; E_max,syst before %.1f '
              'mm, after %.1f mm; plots in %s' % (
                  before['ed'], before['eb'], 1e3 * before['e_max_syst'],
                  1e3 * after['e_max_syst'], workdir))
        self.assertLess(after['e_max_syst'] * float(rospy.get_param('~improvement')),
                        before['e_max_syst'])


if __name__ == '__main__':
    rospy.init_node('physics_umbmark_test')
    rostest.rosrun('rbx1_nav', 'physics_umbmark', PhysicsUmbmarkTest)
