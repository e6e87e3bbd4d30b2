#!/usr/bin/env python3
"""SIGKILL of the course node mid-leg: the simulator stops the robot itself.

Run by out_and_back_killed.test. A killed node sends no stop; the fake
robot's watchdog must stop the base cmd_timeout (give or take one step)
after the last command it ran: measured on ground truth from the time that
command ran from (the robot's own, from its watchdog's log line; not when
this test heard a command, which its clock may put a tick off), the robot
travels between ~min_travel and ~max_travel (m), and then stands still.
"""
import os
import re
import signal
import sys
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import (CourseProcess, RobotWatch, RosoutWatch, TopicLog,  # noqa: E402
                            wait_sim, wait_under_way, wait_until)
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


#: The fake robot's watchdog line: when the command it ran last became due.
WATCHDOG = re.compile(r'no cmd_vel for [\d.]+ s \(the last ran from ([\d.]+) s\); stopping')


def watchdog_ran_from(rosout):
    """The ROS time the robot's last command ran from, by its watchdog's
    line (waiting for it: the robot logs it as it stops)."""
    text = 'no cmd_vel for'
    wait_until(lambda: rosout.find('/fake_turtlebot', text) is not None)
    lines = rosout.all('/fake_turtlebot', text)
    found = WATCHDOG.search(lines[-1].msg) if lines else None
    if not found:
        raise AssertionError('no watchdog line with the time its last command ran '
                             'from: %s' % [line.msg for line in lines])
    return rospy.Time(*divmod(int(round(float(found.group(1)) * 1e9)), 10 ** 9))


class KilledTest(unittest.TestCase):

    def test_sigkill_leaves_the_simulator_to_stop_the_robot(self):
        min_travel = float(rospy.get_param('~min_travel'))
        max_travel = float(rospy.get_param('~max_travel'))
        watch = RobotWatch()
        truth = TruthLog()
        rosout = RosoutWatch()
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
        # From the true pose where the robot's last command ran from, not
        # from one read around the kill: its own travel on that command
        # until its watchdog stopped it.
        ran = watchdog_ran_from(rosout)
        stamp, there = truth.at(ran)
        travel = pose_error(watch.pose(), there)[0]
        print('RESULT killed: last cmd_vel (%.3f m/s) ran from %.3f s (this test heard '
              'one at %.3f s), truth from %.3f s; the robot travelled %.4f m after it '
              '(limits %.4f to %.4f m) and stands at speed %s'
              % (last.linear.x, ran.to_sec(), received.to_sec(), stamp.to_sec(), travel,
                 min_travel, max_travel, speed))
        self.assertEqual(speed, (0.0, 0.0), 'the robot is still moving')
        self.assertGreater(travel, min_travel, 'the watchdog stopped the robot early')
        self.assertLess(travel, max_travel, 'the watchdog stopped the robot late')


if __name__ == '__main__':
    rospy.init_node('out_and_back_killed_test')
    rostest.rosrun('rbx1_nav', 'out_and_back_killed', KilledTest)
