#!/usr/bin/env python3
"""The book's course with default settings on the ideal fake robot.

Run by out_and_back_ideal.test under simulated time. Passes if the node
exits 0 and the simulator's true pose ends within ~position_tolerance and
~heading_tolerance of where it started, with the robot stopped.
"""
import os
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), 'helpers'))
from course_harness import (CourseProcess, RobotWatch,  # noqa: E402
                            check_completed_course)


class IdealCourseTest(unittest.TestCase):

    def test_default_course_returns_to_start(self):
        watch = RobotWatch()
        start = watch.wait_for_truth()
        course = CourseProcess()
        try:
            check_completed_course(self, watch, course, start)
        finally:
            course.cleanup()


if __name__ == '__main__':
    rospy.init_node('out_and_back_ideal_test')
    rostest.rosrun('rbx1_nav', 'out_and_back_ideal', IdealCourseTest)
