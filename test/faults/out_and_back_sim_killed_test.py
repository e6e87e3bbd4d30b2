#!/usr/bin/env python3
"""The simulator dies mid-course: the node must notice, stop and exit 1.

Run by out_and_back_sim_killed.test. Once the robot is well into its first
leg the test kills the fake robot (the clock keeps running). The tf then
goes stale; within ~tf_timeout + 1 s (ROS time) of the simulator's last
message the node must hold the robot (zero velocity) and say so, within
~tf_timeout + ~link_grace + 1 s it must have sent its last stop and logged
the error, and it must then exit with status 1. These deadlines are checked
on ROS time stamps (the stop's arrival, the error's /rosout stamp), in
which the node counts them.

docs/safety.md's promise, exit 1 within tf_timeout + link_grace + 2 s of
losing the robot, is checked on the wall clock, from just before the kill
to the process's end. On a robot ROS time is wall time; here the lockstep
clock runs at up to 5x, never faster, so the ROS-time part (tf_timeout +
link_grace of staleness) takes at most as long in wall time as on a robot
while the clock keeps at least real-time pace. The 2 s cover what is wall
time everywhere: the stop and the error line (at once), rospy's shutdown,
which the node abandons after SHUTDOWN_LIMIT (1 s,
rbx1_nav.common.node_ros.exit_node), and the interpreter's exit. That last
part is also checked alone: from the error line reaching this test to the
process's end, within SHUTDOWN_LIMIT + 1 s.
"""
import os
import sys
import time
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import (CourseProcess, RobotWatch, kill_node,  # noqa: E402
                            RosoutWatch, is_zero, wait_under_way)
from rbx1_nav.common.node_ros import SHUTDOWN_LIMIT  # noqa: E402

EXIT_MARGIN = 2.0  # wall s, docs/safety.md's: stop, error line, teardown, exit


class SimKilledTest(unittest.TestCase):

    def test_stale_tf_stops_the_course(self):
        tf_timeout = float(rospy.get_param('~tf_timeout'))
        grace = float(rospy.get_param('~link_grace'))
        watch = RobotWatch()
        rosout = RosoutWatch()
        start = watch.wait_for_truth()
        course = CourseProcess(params={'tf_timeout': tf_timeout,
                                       'link_grace': grace})
        try:
            wait_under_way(self, watch, start, course)
            killed = time.monotonic()
            kill_node('/fake_turtlebot')
            status = course.wait()
            gone = time.monotonic()
        finally:
            course.cleanup()
        error_seen = course.wall_time_of('Stopped the robot')
        out = course.output
        last_truth = watch.truth.header.stamp
        held_at = rosout.stamp_of(course.node_name, 'Holding the robot')
        error_at = rosout.stamp_of(course.node_name, 'Stopped the robot')
        self.assertIsNotNone(held_at, out)
        self.assertIsNotNone(error_at, out)
        stop_at, last = watch.last_command()
        print('RESULT sim_killed exit=%d; after the last ground_truth: robot '
              'held at +%.2f s, error logged at +%.2f s, last (zero) cmd_vel '
              'at +%.2f s, process gone at +%.2f s (ROS time); process gone '
              '%.2f s (wall) after the kill, %.2f s after its error line '
              '(limits %.1f s and %.1f s)' % (
                  status, (held_at - last_truth).to_sec(),
                  (error_at - last_truth).to_sec(),
                  (stop_at - last_truth).to_sec(),
                  (course.exit_time - last_truth).to_sec(),
                  gone - killed, gone - (error_seen or gone),
                  tf_timeout + grace + EXIT_MARGIN, SHUTDOWN_LIMIT + 1.0))
        self.assertEqual(status, 1, out)
        self.assertTrue(is_zero(last), 'last cmd_vel was %s' % last)
        self.assertGreater(stop_at, last_truth, 'no stop sent after the sim died')
        self.assertLess((held_at - last_truth).to_sec(), tf_timeout + 1.0, out)
        self.assertLess((error_at - last_truth).to_sec(), tf_timeout + grace + 1.0, out)
        self.assertLess((stop_at - last_truth).to_sec(), tf_timeout + grace + 1.0, out)
        self.assertIsNotNone(error_seen, out)
        self.assertLess(gone - error_seen, SHUTDOWN_LIMIT + 1.0, out)
        self.assertLess(gone - killed, tf_timeout + grace + EXIT_MARGIN, out)


if __name__ == '__main__':
    rospy.init_node('out_and_back_sim_killed_test')
    rostest.rosrun('rbx1_nav', 'out_and_back_sim_killed', SimKilledTest)
