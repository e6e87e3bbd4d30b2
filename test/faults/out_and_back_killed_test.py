#!/usr/bin/env python3
"""SIGKILL of the course node mid-leg: the simulator stops the robot itself.

Run by out_and_back_killed.test. A killed node sends no stop; the fake
robot's watchdog must stop the base cmd_timeout (give or take one step)
after the last command it received: measured on ground truth from the
last cmd_vel's time, the robot travels between ~min_travel and
~max_travel (m), and then stands still.
"""
import os
import signal
import sys
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import (CourseProcess, RobotWatch, TopicLog,  # noqa: E402
                            wait_sim, wait_under_way)
from rbx1_nav.motion.course.command import pose_error  # noqa: E402
from rbx1_nav.transform_utils import Pose2D, quat_to_angle  # noqa: E402


class TruthLog(TopicLog):
    """Every ground_truth of the robot: (stamp, Pose2D), in order."""

    def __init__(self):
        TopicLog.__init__(self, 'ground_truth', Odometry, lambda msg: (
            msg.header.stamp, Pose2D(msg.pose.pose.position.x, msg.pose.pose.position.y,
                                     quat_to_angle(msg.pose.pose.orientation))))

    def at(self, stamp):
        """The first (stamp, pose) at or after ``stamp``."""
        with self.lock:
            return next(((t, pose) for t, pose in self.records if t >= stamp), (None, None))


class KilledTest(unittest.TestCase):

    def test_sigkill_leaves_the_simulator_to_stop_the_robot(self):
        min_travel = float(rospy.get_param('~min_travel'))
        max_travel = float(rospy.get_param('~max_travel'))
        watch = RobotWatch()
        truth = TruthLog()
        start = watch.wait_for_truth()
        course = CourseProcess()
        try:
            wait_under_way(self, watch, start, course)
            course.proc.send_signal(signal.SIGKILL)
            course.wait(wall_limit=10.0)
        finally:
            course.cleanup()
        wait_sim(1.0)  # cmd_timeout (0.5 s) and then some
        received, last = watch.last_command()
        speed = watch.true_speed()
        # From the true pose at the last command the robot received (the
        # first ground_truth stamped at or after the test heard it, the
        # same ROS time under lockstep), not from one read around the
        # kill: the robot's own travel on its last command until its
        # watchdog stopped it.
        stamp, there = truth.at(received)
        travel = pose_error(watch.pose(), there)[0]
        print('RESULT killed: last cmd_vel (%.3f m/s) at %.3f s, truth from %.3f s; '
              'the robot travelled %.4f m after it (limits %.3f to %.3f m) and stands at '
              'speed %s' % (last.linear.x, received.to_sec(), stamp.to_sec(), travel,
                            min_travel, max_travel, speed))
        self.assertEqual(speed, (0.0, 0.0), 'the robot is still moving')
        self.assertGreater(travel, min_travel, 'the watchdog stopped the robot early')
        self.assertLess(travel, max_travel, 'the watchdog stopped the robot late')


if __name__ == '__main__':
    rospy.init_node('out_and_back_killed_test')
    rostest.rosrun('rbx1_nav', 'out_and_back_killed', KilledTest)
