#!/usr/bin/env python3
"""A driver that publishes NaN poses is named as such, never reported as absent.

Run by nan_driver.test. The stand-in driver (test/helpers/nan_driver.py, started here for each
case) publishes ``odom``, ``odom -> base_footprint`` on /tf and ``odom_combined`` with NaN in
the position and the quaternion, as ROBOTIS' turtlebot3_fake_node does without its model, and
records every command it receives on ``cmd_vel``. tf2 drops NaN transforms, so a course that
only asks tf sees no robot at all.

* From the start: the course exits 1 with an error naming the driver's node and NaN (not
  "nothing is publishing"), and the driver never received a command to move; pose_ekf and
  odom_ekf name the node their dropped readings come from.
* Mid-course (``~nan_after_motion``: a valid pose until the first command to move, then NaN):
  the course stops the robot and exits 1 naming the node and NaN; the driver's last command,
  once the course is gone, is a zero.

No lockstep and no simulated clock: nothing moves (the stand-in has no model of motion), and
each verdict is what arrived, not when. The start-up wait (~tf_wait) is wall time by design, a
deadline the stand-in, already publishing at 25 Hz before the course starts, fills some 50
times over; mid-course the stand-in turns to NaN on the course's first command to move, which
the course cannot end before (it drives 1 m and the pose never changes).
"""
import json
import os
import sys
import threading
import unittest

import rospy
import rostest
from std_srvs.srv import Trigger
from tf2_msgs.msg import TFMessage

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import WALL_LIMIT, CourseProcess, wait_until  # noqa: E402

DRIVER = '/nan_driver'


class Driver(object):
    """The stand-in driver, as rosrun runs it, and what it received."""

    def __init__(self, **params):
        self.heard = threading.Event()
        self.sub = rospy.Subscriber('/tf', TFMessage, self._on_tf)
        self.proc = CourseProcess(script='nan_driver.py', name=DRIVER[1:], params=params)
        self.received_srv = rospy.ServiceProxy(DRIVER + '/received', Trigger)

    def _on_tf(self, msg):
        if msg._connection_header['callerid'] == DRIVER:
            self.heard.set()

    def wait_up(self, test):
        """Until this test hears the driver's transform (it runs); fails at once if it ended."""
        wait_until(lambda: self.heard.is_set() or not self.proc.running())
        test.assertTrue(self.heard.is_set(), 'the stand-in driver never published:\n%s'
                        % self.proc.output)
        self.sub.unregister()

    def commands(self, test):
        """[(node, linear.x, angular.z)] the driver received, once no node publishes on its
        cmd_vel any more (the course gone, everything it sent delivered)."""
        answer = {}

        def settled():
            answer.update(json.loads(self.received_srv().message))
            return answer['connections'] == 0

        test.assertTrue(wait_until(settled), 'a node still publishes on cmd_vel after %.0f s'
                        % WALL_LIMIT)
        return [tuple(c) for c in answer['commands']]

    def close(self):
        self.proc.interrupt()
        self.proc.finish()


def line_with(test, node, text):
    """The first line ``node`` (a CourseProcess) prints with ``text``, waiting for it; fails
    at once if the node ends first."""
    wait_until(lambda: text in node.output or node.ended())
    found = [line for line in node.lines if text in line]
    test.assertTrue(found, 'no line with %r:\n%s' % (text, node.output))
    return found[0]


class NanDriverTest(unittest.TestCase):

    def test_a_nan_from_the_start_is_named_not_absent(self):
        tf_wait = float(rospy.get_param('~tf_wait'))
        driver = Driver()
        filters = []
        try:
            driver.wait_up(self)
            course = CourseProcess(params={'tf_wait': tf_wait})
            filters = [CourseProcess(script='pose_ekf.py', name='robot_pose_ekf',
                                     params={'imu_used': 'false', 'publish_tf': 'false',
                                             'sensor_timeout': 2.0}),
                       CourseProcess(script='odom_ekf.py', name='odom_ekf')]
            status = course.finish()
            out = course.output
            commands = driver.commands(self)
            moving = [c for c in commands if c[1] or c[2]]
            print('RESULT nan_driver start exit=%d, %d commands received, %d to move'
                  % (status, len(commands), len(moving)))
            self.assertEqual(status, 1, out)
            self.assertEqual(moving, [], out)
            self.assertIn('tf odom -> base_footprint comes from %s, but all ' % DRIVER, out)
            self.assertIn('were invalid (NaN in the position (nan, nan, 0) and the rotation '
                          '(0, 0, nan, nan))', out)
            self.assertIn('Fix %s' % DRIVER, out)
            self.assertNotIn('nothing is publishing', out)
            self.assertIn('/odom from %s is invalid (NaN' % DRIVER, out)
            # Each filter's first dropped reading, and pose_ekf's word ~sensor_timeout after
            # start-up on the sensor that gave it nothing it could use.
            pose_ekf, odom_ekf = filters
            self.assertIn('dropped odom on /odom from %s: bad orientation: quaternion has a '
                          'non-finite component' % DRIVER,
                          line_with(self, pose_ekf, 'dropped odom on /odom'))
            silent = line_with(self, pose_ekf, 'odom_used is true but')
            self.assertIn('every reading on /odom in the 2 s since start-up was dropped', silent)
            self.assertIn('fix %s, which publishes it' % DRIVER, silent)
            self.assertIn('dropped pose on /odom_combined from %s: bad orientation' % DRIVER,
                          line_with(self, odom_ekf, 'dropped pose on /odom_combined'))
        finally:
            for node in filters:
                node.interrupt()
                node.finish()
            driver.close()

    def test_b_nan_mid_course_stops_the_robot(self):
        tf_wait = float(rospy.get_param('~tf_wait'))
        driver = Driver(nan_after_motion='true')
        try:
            driver.wait_up(self)
            course = CourseProcess(params={'tf_wait': tf_wait})
            status = course.finish()
            out = course.output
            commands = driver.commands(self)
        finally:
            driver.close()
        moving = [c for c in commands if c[1] or c[2]]
        print('RESULT nan_driver mid-course exit=%d, %d commands received, %d to move, the '
              'last %s' % (status, len(commands), len(moving), commands[-1:]))
        self.assertEqual(status, 1, out)
        self.assertTrue(moving, 'the course never drove: %s\n%s' % (commands, out))
        self.assertEqual(commands[-1], ('/odom_out_and_back', 0.0, 0.0), out)
        self.assertIn('tf odom -> base_footprint from %s is invalid (NaN in the position '
                      '(nan, nan, 0) and the rotation (0, 0, nan, nan))' % DRIVER, out)
        self.assertIn('Stopped the robot', out)


if __name__ == '__main__':
    rospy.init_node('nan_driver_course')
    rostest.rosrun('rbx1_nav', 'nan_driver_course', NanDriverTest)
