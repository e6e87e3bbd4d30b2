#!/usr/bin/env python3
"""Under lockstep, the ROS graph drives exactly the pure model's course.

The course node (odom_out_and_back.py with ~course_params) runs against the
fake robot under lockstep simulated time, with ~burners CPU-burning
processes beside it. The reference is the same course run in plain Python
on the simulator's own model (test/helpers/course_model.py: the ideal
robot, each command held for one control period): what the graph does
when no message is late. The true end pose must match it within
~match_position (m) and ~match_heading (deg), whatever the clock's speed
(the .test files run it at 1x and at max with burners) and the load, and
end within ~position_tolerance (m) and ~heading_tolerance (deg) of the
start, the robot stopped; each of ~expect_in_output (strings) must be in
the course's log.
"""
import math
import os
import subprocess
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import (CourseProcess, RobotWatch,  # noqa: E402
                            check_completed_course)

from course_model import reference_end_pose  # noqa: E402
from rbx1_nav.transform_utils import normalize_angle  # noqa: E402

BURN = 'while True: pass'


class LockstepCourseTest(unittest.TestCase):

    def test_graph_matches_the_model_under_load(self):
        params = rospy.get_param('~course_params', {})
        expected = reference_end_pose(params)
        burners = [subprocess.Popen([sys.executable, '-c', BURN])
                   for _ in range(int(rospy.get_param('~burners', 0)))]
        try:
            watch = RobotWatch()
            start = watch.wait_for_truth()
            course = CourseProcess(params=params)
            try:
                check_completed_course(self, watch, course, start)
                for text in rospy.get_param('~expect_in_output', []):
                    self.assertIn(text, course.output)
            finally:
                course.cleanup()
        finally:
            for proc in burners:
                proc.kill()
                proc.wait()
        final = watch.pose()
        dx, dy = final.x - expected.x, final.y - expected.y
        dyaw = math.degrees(normalize_angle(final.yaw - expected.yaw))
        print('RESULT lockstep end pose (%.6f, %.6f, %.4f deg), model (%.6f, '
              '%.6f, %.4f deg): off by %.4f mm, %.5f deg'
              % (final.x, final.y, math.degrees(final.yaw), expected.x,
                 expected.y, math.degrees(expected.yaw),
                 1000 * math.hypot(dx, dy), dyaw))
        self.assertLess(math.hypot(dx, dy),
                        float(rospy.get_param('~match_position')))
        self.assertLess(abs(dyaw), float(rospy.get_param('~match_heading')))


if __name__ == '__main__':
    rospy.init_node('lockstep_course_test')
    rostest.rosrun('rbx1_nav', 'lockstep_course', LockstepCourseTest)
