#!/usr/bin/env python3
"""rostest: the out-and-back course ends better aligned through the EKF.

ekf_out_and_back.test runs the same realistic robot twice on one clock: in
one namespace the course follows raw wheel odometry, in the other the tf
published by pose_ekf.py (wheels + gyro). Each course node exits when its
course is done. Each course must have completed as check_completed_course
(test/helpers/course_harness.py) has it: its node exited 0 after logging
"Course complete" (read from rostest's and the node's log files, since the
.test, not this test, started it), and the robot is stopped (true speed
zero, last cmd_vel a stop) within ~max_end_distance of where it started.
This test then reads each robot's ground_truth and compares the final
heading with the heading at the start (two half turns: the robot should
face where it started). Both figures are printed.
"""
import math
import os
import sys
import threading
import unittest

import rosgraph
import rospy
import rostest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import (MASTER_POLL, is_zero, launched_node_status,  # noqa: E402
                            node_registered)
from rbx1_nav.transform_utils import normalize_angle, quat_to_angle  # noqa: E402


class Track(object):
    """Ground truth of one robot: first and latest pose, farthest
    excursion; and the last cmd_vel its course sent."""

    def __init__(self, ns):
        self.ns = ns
        self.lock = threading.Lock()
        self.first = self.latest = None
        self.farthest = 0.0
        self.last_cmd = None
        self.sub = rospy.Subscriber('/%s/ground_truth' % ns, Odometry,
                                    self.on_truth, queue_size=50)
        self.cmd_sub = rospy.Subscriber('/%s/cmd_vel' % ns, Twist,
                                        self.on_cmd, queue_size=50)

    def on_cmd(self, msg):
        with self.lock:
            self.last_cmd = msg

    def on_truth(self, msg):
        pose = msg.pose.pose
        reading = (pose.position.x, pose.position.y,
                   quat_to_angle(pose.orientation),
                   abs(msg.twist.twist.linear.x) + abs(msg.twist.twist.angular.z))
        with self.lock:
            if self.first is None:
                self.first = reading
            self.latest = reading
            self.farthest = max(self.farthest, math.hypot(
                reading[0] - self.first[0], reading[1] - self.first[1]))

    def end_distance(self):
        """Distance from the start to the latest true position, in metres."""
        with self.lock:
            return math.hypot(self.latest[0] - self.first[0],
                              self.latest[1] - self.first[1])

    def heading_error(self):
        """Final minus initial true heading, in radians."""
        with self.lock:
            return normalize_angle(self.latest[2] - self.first[2])


class EkfOutAndBackTest(unittest.TestCase):
    """Raw odometry versus the fused estimate on the same course."""

    def check_completed(self, ns, track, max_end):
        """What check_completed_course asserts, for a course node the .test
        started: exit status 0, "Course complete" logged, the robot stopped
        near its start."""
        status, log = launched_node_status('%s/odom_out_and_back' % ns)
        self.assertEqual(status, 0, '%s: the course exited %s:\n%s'
                         % (ns, status, log))
        self.assertIn('Course complete', log)
        self.assertLess(track.end_distance(), max_end,
                        '%s: the course ended %.2f m from the start'
                        % (ns, track.end_distance()))
        with track.lock:
            speed, last = track.latest[3], track.last_cmd
        self.assertEqual(speed, 0.0, '%s: robot still moving' % ns)
        self.assertTrue(last is not None and is_zero(last),
                        '%s: last cmd_vel was not a stop: %s' % (ns, last))

    def test_fused_course_ends_with_smaller_heading_error(self):
        namespaces = rospy.get_param('~namespaces', 'raw ekf').split()
        raw_ns, ekf_ns = namespaces
        timeout = rospy.Duration(float(rospy.get_param('~timeout', 300.0)))
        max_ratio = float(rospy.get_param('~max_error_ratio', 0.25))
        max_end = float(rospy.get_param('~max_end_distance', 0.3))
        tracks = {ns: Track(ns) for ns in namespaces}
        master = rosgraph.Master(rospy.get_name())

        deadline = rospy.Time.now() + timeout
        while any(t.first is None for t in tracks.values()):
            self.assertLess(rospy.Time.now(), deadline, 'no ground_truth')
            rospy.sleep(0.1)
        for ns, track in tracks.items():
            self.assertLess(track.first[3], 1e-6,
                            '%s: the robot was already moving when the test '
                            'started; raise the course ~start_delay' % ns)

        # A course is over when its node, once seen registered, is gone.
        pending, seen = set(namespaces), set()
        while pending and not rospy.is_shutdown():
            for ns in list(pending):
                if node_registered(master, '/%s/odom_out_and_back' % ns):
                    seen.add(ns)
                elif ns in seen:
                    pending.discard(ns)
            self.assertLess(rospy.Time.now(), deadline,
                            'course not over in %s: %s' % (
                                timeout.to_sec(), ' '.join(sorted(pending))))
            rospy.rostime.wallsleep(MASTER_POLL)
        rospy.sleep(1.0)  # let the robots coast to a stop
        for ns, track in tracks.items():
            self.assertGreater(track.farthest, 0.5, '%s: the robot never went '
                               'out (%.2f m at most)' % (ns, track.farthest))
            self.check_completed(ns, track, max_end)

        raw = abs(tracks[raw_ns].heading_error())
        fused = abs(tracks[ekf_ns].heading_error())
        report = ('ground-truth heading error at the end of the course: '
                  'raw odometry %.2f deg, fused (pose_ekf) %.2f deg'
                  % (math.degrees(raw), math.degrees(fused)))
        print(report, flush=True)
        rospy.loginfo(report)
        self.assertLess(fused, max_ratio * raw,
                        report + '; want fused < %.2f x raw' % max_ratio)


if __name__ == '__main__':
    rospy.init_node('ekf_out_and_back_test')
    rostest.rosrun('rbx1_nav', 'ekf_out_and_back', EkfOutAndBackTest)
