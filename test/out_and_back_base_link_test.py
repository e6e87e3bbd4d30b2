#!/usr/bin/env python3
"""A robot whose odometry frame is odom -> base_link (no base_footprint).

Run by out_and_back_base_link.test. With ~base_frame left empty the node
must find base_link by itself, as the book's node did, and finish.
"""
import os
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), 'helpers'))
from course_harness import (CourseProcess, RobotWatch,  # noqa: E402
                            check_completed_course)


class BaseLinkTest(unittest.TestCase):

    def test_base_link_is_detected_and_course_completes(self):
        watch = RobotWatch()
        start = watch.wait_for_truth()
        course = CourseProcess()
        try:
            check_completed_course(self, watch, course, start)
        finally:
            course.cleanup()
        self.assertIn('Following tf odom -> base_link', course.output)


if __name__ == '__main__':
    rospy.init_node('out_and_back_base_link_test')
    rostest.rosrun('rbx1_nav', 'out_and_back_base_link', BaseLinkTest)
