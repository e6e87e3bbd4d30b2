#!/usr/bin/env python3
"""ROS time jumps back mid-course: the node names it, stops and exits 1.

Run by out_and_back_clock_jump.test. Once the robot is well into its first
leg, the test replaces sim_clock by one that starts ~jump seconds earlier
(a looping bag, a restarted simulator). The course node must log "ROS time
moved backwards by <jump> s", leave the robot stopped (its last cmd_vel a
zero Twist) and exit 1; the simulator must keep publishing from the new
time. The course's ~tf_timeout is 15 s so the node's wait for its next
lockstep grant (max(4 s, ~tf_timeout) of wall time) does not end while
the new clock starts, which takes several seconds on a loaded machine.
"""
import os
import re
import subprocess
import sys
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import (CourseProcess, RobotWatch,  # noqa: E402
                            is_zero, kill_node, wait_under_way, wait_until)
from rosrun import rosrun  # noqa: E402


class ClockJumpTest(unittest.TestCase):

    def test_time_moving_backwards_stops_the_course(self):
        jump = float(rospy.get_param('~jump'))
        watch = RobotWatch()
        # Every stamp the simulator publishes: at 5x the new clock is past
        # the jump's middle a second after it starts, maybe before the
        # course has exited.
        stamps = []
        rospy.Subscriber('ground_truth', Odometry, lambda msg: stamps.append(
            msg.header.stamp.to_sec()), queue_size=1000)
        start = watch.wait_for_truth()
        course = CourseProcess(params={'tf_timeout': 15.0})
        clock = None
        try:
            # Moving, and late enough that the new clock's start is > 0.
            wait_under_way(self, watch, start, course, also=lambda: (
                watch.truth.header.stamp.to_sec() > jump + 1.0))
            kill_node('/sim_clock')
            back_to = watch.truth.header.stamp.to_sec() - jump
            killed = len(stamps)
            clock = subprocess.Popen(
                rosrun('rbx1_nav', 'sim_clock.py', '__name:=sim_clock',
                 '_speed:=5', '_start_time:=%.3f' % back_to),
                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            status = course.wait()
            self.assertTrue(wait_until(
                lambda: any(t < back_to + jump / 2 for t in stamps[killed:])),
                'the simulator stopped at the jump:\n' + course.output)
        finally:
            course.cleanup()
            if clock:
                clock.terminate()
                clock.wait()
        out = course.output
        _, last = watch.last_command()
        found = re.search(r'ROS time moved backwards by ([\d.]+) s', out)
        # The jump the course logged: the old clock ran on (at 5x) until
        # rosnode kill took effect, as the wall clock has it.
        print('RESULT clock_jump exit=%d, logged a jump of %s s (wall-timed), '
              'last cmd_vel zero: %s' % (status, found and found.group(1),
                                          last is not None and is_zero(last)))
        self.assertEqual(status, 1, out)
        self.assertIsNotNone(found, out)
        self.assertAlmostEqual(float(found.group(1)), jump, delta=1.0)
        self.assertIn('a bag looping or the simulator restarted?', out)
        self.assertTrue(last is not None and is_zero(last),
                        'last cmd_vel was %s' % last)


if __name__ == '__main__':
    rospy.init_node('out_and_back_clock_jump_test')
    rostest.rosrun('rbx1_nav', 'out_and_back_clock_jump', ClockJumpTest)
