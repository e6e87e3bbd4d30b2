#!/usr/bin/env python3
"""One course on the fake robot, judged on its true end pose.

Shared by the course tests: out_and_back_precise.test (~precise),
out_and_back_base_link.test (a robot with no base_footprint),
timed_out_and_back*.test and nav_square*.test. (The odometry course in the
book's mode on the ideal robot is checked by lockstep_course_test.py, in
lockstep_1x.test and lockstep_max_loaded.test.)
~node names the course node (odom_out_and_back.py by default); every one of
these courses ends where it began. Passes if the node exits 0 and the
simulator's ground_truth ends within ~position_tolerance (m) and
~heading_tolerance (deg) of the start, with the robot stopped.
~course_params (dict) go to the course node as private parameters; every
string in ~expect_in_output must appear in its log.
"""
import os
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import (CourseProcess, RobotWatch,  # noqa: E402
                            check_completed_course)


class CourseTest(unittest.TestCase):

    def test_course_returns_to_start(self):
        watch = RobotWatch()
        start = watch.wait_for_truth()
        course = CourseProcess(params=rospy.get_param('~course_params', {}),
                               script=rospy.get_param('~node',
                                                      'odom_out_and_back.py'))
        try:
            check_completed_course(self, watch, course, start)
        finally:
            course.cleanup()
        for text in rospy.get_param('~expect_in_output', []):
            self.assertIn(text, course.output)


if __name__ == '__main__':
    rospy.init_node('out_and_back_course_test')
    rostest.rosrun('rbx1_nav', 'out_and_back_course', CourseTest)
