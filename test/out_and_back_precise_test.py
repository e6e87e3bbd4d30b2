#!/usr/bin/env python3
"""Precise mode (~precise true) on the ideal fake robot.

Run by out_and_back_precise.test under simulated time. Slowing down near
each goal should bring the true end pose to within ~position_tolerance and
~heading_tolerance of the start, far tighter than the book's mode.
"""
import os
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), 'helpers'))
from course_harness import (CourseProcess, RobotWatch,  # noqa: E402
                            check_completed_course)


class PreciseCourseTest(unittest.TestCase):

    def test_precise_course_returns_to_start(self):
        watch = RobotWatch()
        start = watch.wait_for_truth()
        course = CourseProcess(params={'precise': 'true'})
        try:
            check_completed_course(self, watch, course, start)
        finally:
            course.cleanup()
        self.assertIn('precise on', course.output)


if __name__ == '__main__':
    rospy.init_node('out_and_back_precise_test')
    rostest.rosrun('rbx1_nav', 'out_and_back_precise', PreciseCourseTest)
