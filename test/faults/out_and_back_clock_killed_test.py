#!/usr/bin/env python3
"""The simulated clock dies mid-course: the node must stop and exit 1.

Run by out_and_back_clock_killed.test. Under /use_sim_time a dead /clock
freezes ROS time, so rospy sleeps would block forever; the node's wall-time
watchdog must notice, send a stop, log why, and exit 1 within a wall-time
bound derived from its parameters (:func:`exit_limit`). Time here is
measured on the wall clock, since ROS time stands still once the clock is
gone: how long a robot keeps its last command after its clock dies is a
real safety latency.
"""
import os
import sys
import time
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import (CourseProcess, RobotWatch, kill_node,  # noqa: E402
                            is_zero, launched_node_status, wait_under_way)
from rbx1_nav.sim_time import member_ros as lockstep  # noqa: E402
from rbx1_nav.sim_time import switch_ros  # noqa: E402
from rbx1_nav.common.node_ros import SHUTDOWN_LIMIT  # noqa: E402

EXIT = 1.0  # wall s for the interpreter to exit once rospy is shut down


def exit_limit(tf_timeout):
    """Wall s from the clock's death to the node's exit, at most.

    The node notices a dead clock by waiting for it on the wall clock:
    under lockstep for its next grant, max(GRANT_LIMIT, tf_timeout) with
    sim_clock's connection closed, checked every POLL s
    (rbx1_nav.sim_time.course_member_ros); otherwise its ClockWatchdog,
    max(2 s, tf_timeout) (rbx1_nav.sim_time.clock_watch_ros). Both waits begin at the
    last tick, before the kill. Then it stops the robot and logs why (at
    once), rospy's shutdown takes up to SHUTDOWN_LIMIT (then the node
    exits without it, rbx1_nav.common.node_ros.exit_node), and the
    interpreter's exit up to EXIT.
    """
    if switch_ros.lockstep():
        notice = lockstep.POLL + max(lockstep.GRANT_LIMIT, tf_timeout)
    else:
        notice = max(2.0, tf_timeout)
    return notice + SHUTDOWN_LIMIT + EXIT


class ClockKilledTest(unittest.TestCase):

    def test_dead_clock_stops_the_course(self):
        tf_timeout = 1.0  # the node's default
        exit_within = exit_limit(tf_timeout)
        watch = RobotWatch()
        start = watch.wait_for_truth()
        course = CourseProcess(params={'tf_timeout': tf_timeout})
        try:
            wait_under_way(self, watch, start, course)
            kill_node('/sim_clock')
            killed = time.monotonic()
            status = course.wait(wall_limit=4 * exit_within)
            took = time.monotonic() - killed
        finally:
            course.cleanup()
        _, last = watch.last_command()
        print('RESULT clock_killed exit=%d after %.2f s wall (limit %.1f s); '
              'last cmd_vel zero: %s' % (status, took, exit_within,
                                         last is not None and is_zero(last)))
        self.assertEqual(status, 1, course.output)
        self.assertIn('/clock has not advanced', course.output)
        self.assertLess(took, exit_within, course.output)
        self.assertTrue(last is not None and is_zero(last),
                        'last cmd_vel was %s' % last)
        # sim_clock, killed, does not take its own connections closing for
        # its members leaving.
        _, clock_log = launched_node_status('sim_clock')
        self.assertNotIn('without a word', clock_log)


if __name__ == '__main__':
    rospy.init_node('out_and_back_clock_killed_test')
    rostest.rosrun('rbx1_nav', 'out_and_back_clock_killed', ClockKilledTest)
