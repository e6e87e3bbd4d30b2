#!/usr/bin/env python3
"""The simulated clock dies mid-course: the node must stop and exit 1.

Run by out_and_back_clock_killed.test. Under /use_sim_time a dead /clock
freezes ROS time, so rospy sleeps would block forever; the node's wall-time
watchdog must notice, send a stop, log why, and exit 1 within ~exit_within
wall seconds of the kill. Time here is measured on the wall clock, since
ROS time stands still once the clock is gone.
"""
import os
import sys
import time
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import (CourseProcess, RobotWatch, kill_node,  # noqa: E402
                            is_zero, wait_under_way)


class ClockKilledTest(unittest.TestCase):

    def test_dead_clock_stops_the_course(self):
        exit_within = float(rospy.get_param('~exit_within'))
        watch = RobotWatch()
        start = watch.wait_for_truth()
        course = CourseProcess()
        try:
            wait_under_way(self, watch, start, course)
            kill_node('/sim_clock')
            killed = time.monotonic()
            status = course.wait(wall_limit=4 * exit_within)
            took = time.monotonic() - killed
        finally:
            course.cleanup()
        _, last = watch.last_command()
        print('RESULT clock_killed exit=%d after %.2f s wall; last cmd_vel '
              'zero: %s' % (status, took, last is not None and is_zero(last)))
        self.assertEqual(status, 1, course.output)
        self.assertIn('/clock has not advanced', course.output)
        self.assertLess(took, exit_within, course.output)
        self.assertTrue(last is not None and is_zero(last),
                        'last cmd_vel was %s' % last)


if __name__ == '__main__':
    rospy.init_node('out_and_back_clock_killed_test')
    rostest.rosrun('rbx1_nav', 'out_and_back_clock_killed', ClockKilledTest)
