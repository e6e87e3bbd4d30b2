#!/usr/bin/env python3
"""No robot at all: the node must give up cleanly without moving.

Run by out_and_back_no_tf.test: a lockstep clock but no simulator, so no
odom -> base transform ever appears. Expect an error naming the frames
tried and what publishes them ~tf_wait seconds after the node starts
waiting (within ~grace), exit status 1, and not one motion command on
cmd_vel (not sooner than ~tf_wait less a quarter of ~grace: the lines'
arrival lags their writing a little on a loaded machine). Under lockstep the start-up waits count wall seconds (they wait
for other processes), so the times are those at which the node's two
lines arrive; process start-up and teardown do not count.
"""
import os
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import CourseProcess, RobotWatch  # noqa: E402


class NoTfTest(unittest.TestCase):

    def test_gives_up_with_a_clear_error_and_never_moves(self):
        tf_wait = float(rospy.get_param('~tf_wait'))
        grace = float(rospy.get_param('~grace'))
        watch = RobotWatch()
        course = CourseProcess(params={'tf_wait': tf_wait})
        status = course.finish()
        out = course.output
        self.assertEqual(status, 1, out)
        began = course.wall_time_of('Waiting up to')
        gave_up = course.wall_time_of('no transform')
        self.assertIsNotNone(began, out)
        self.assertIsNotNone(gave_up, out)
        waited = gave_up - began
        print('RESULT no_tf exit=%d, gave up %.2f s (wall time) after it '
              'began waiting' % (status, waited))
        # ~tf_wait is wall time by design (the node waits for other
        # processes, not for the robot), so the bounds are wall time too.
        # The node checks its deadline every 1/20 s (TfFollower.
        # find_base_frame), so it gives up 0 to 0.05 s after ~tf_wait; what
        # this test sees adds each line's passage through the pipe to its
        # reader (35 ms seen on a loaded machine). ~grace covers that
        # passage: a quarter of it before (the first line late shortens the
        # wait seen), all of it after. A node counting ROS time (10x here)
        # would give up after 0.5 s, one that never gives up not at all.
        self.assertGreaterEqual(waited, tf_wait - grace / 4.0, out)
        self.assertLess(waited, tf_wait + grace, out)
        self.assertIn('no transform from odom to base_footprint or base_link', out)
        self.assertIn('fake_turtlebot.launch', out)
        self.assertIn('driver', out)
        self.assertEqual(watch.motion_commands(), [])


if __name__ == '__main__':
    rospy.init_node('out_and_back_no_tf_test')
    rostest.rosrun('rbx1_nav', 'out_and_back_no_tf', NoTfTest)
