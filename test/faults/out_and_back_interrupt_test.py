#!/usr/bin/env python3
"""Ctrl-C mid-course: the node must send a stop before it exits.

Run by out_and_back_interrupt.test. SIGINT (what Ctrl-C sends) goes to the
node during the first leg; the last cmd_vel must be a stop, the robot must
be standing still (the .test disables the simulator's own command watchdog,
so only the node's stop can do that), and the exit status must not claim
success.
"""
import os
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import (CourseProcess, RobotWatch, is_zero,  # noqa: E402
                            wait_sim, wait_under_way)


class InterruptTest(unittest.TestCase):

    def test_ctrl_c_stops_the_robot(self):
        settle = float(rospy.get_param('~settle'))
        watch = RobotWatch()
        start = watch.wait_for_truth()
        course = CourseProcess()
        try:
            wait_under_way(self, watch, start, course)
            course.interrupt()
            status = course.wait()
        finally:
            course.cleanup()
        wait_sim(settle)
        stamp, last = watch.last_command()
        speed = watch.true_speed()
        print('RESULT interrupt exit=%d last_cmd_zero=%s speed=%s'
              % (status, is_zero(last), speed))
        self.assertNotEqual(status, 0, course.output)
        self.assertTrue(is_zero(last), 'last cmd_vel was %s' % last)
        self.assertEqual(speed, (0.0, 0.0))


if __name__ == '__main__':
    rospy.init_node('out_and_back_interrupt_test')
    rostest.rosrun('rbx1_nav', 'out_and_back_interrupt', InterruptTest)
