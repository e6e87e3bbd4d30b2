#!/usr/bin/env python3
"""SIGKILL of the course node mid-leg: the simulator stops the robot itself.

Run by out_and_back_killed.test. A killed node sends no stop; the fake
robot's watchdog must stop the base cmd_timeout (plus at most one step)
after the last command it received, so the robot travels at most
~max_travel (m) after the kill, and then stands still.
"""
import os
import signal
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import (CourseProcess, RobotWatch, wait_sim,  # noqa: E402
                            wait_under_way)


class KilledTest(unittest.TestCase):

    def test_sigkill_leaves_the_simulator_to_stop_the_robot(self):
        max_travel = float(rospy.get_param('~max_travel'))
        watch = RobotWatch()
        start = watch.wait_for_truth()
        course = CourseProcess()
        try:
            wait_under_way(self, watch, start, course)
            at_kill = watch.pose()
            course.proc.send_signal(signal.SIGKILL)
            course.wait(wall_limit=10.0)
        finally:
            course.cleanup()
        wait_sim(1.0)  # cmd_timeout (0.5 s) and then some
        travel = watch.moved_since(at_kill)
        speed = watch.true_speed()
        # From the pose read before the kill: the simulator may step on
        # meanwhile, as the wall clock has it.
        print('RESULT killed: the robot travelled %.3f m (wall-timed) after SIGKILL (limit '
              '%.3f m) and stands at speed %s' % (travel, max_travel, speed))
        self.assertEqual(speed, (0.0, 0.0), 'the robot is still moving')
        self.assertLess(travel, max_travel)


if __name__ == '__main__':
    rospy.init_node('out_and_back_killed_test')
    rostest.rosrun('rbx1_nav', 'out_and_back_killed', KilledTest)
