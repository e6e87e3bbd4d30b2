#!/usr/bin/env python3
"""rostest: the out-and-back course ends better aligned through the EKF.

ekf_out_and_back.test runs the same realistic robot twice on one clock: in
one namespace the course follows raw wheel odometry, in the other the tf
published by pose_ekf.py (wheels + gyro). Each course node exits when its
course is done; this test then reads each robot's ground_truth and compares
the final heading with the heading at the start (two half turns: the robot
should face where it started). Both figures are printed.
"""
import math
import threading
import unittest

import rosgraph
import rospy
import rostest
from nav_msgs.msg import Odometry

from rbx1_nav.transform_utils import normalize_angle, quat_to_angle


class Track(object):
    """Ground truth of one robot: first and latest pose, farthest excursion."""

    def __init__(self, ns):
        self.ns = ns
        self.lock = threading.Lock()
        self.first = self.latest = None
        self.farthest = 0.0
        self.sub = rospy.Subscriber('/%s/ground_truth' % ns, Odometry,
                                    self.on_truth, queue_size=50)

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

    def course_running(self, master, ns):
        """Whether /ns/odom_out_and_back is still registered."""
        node = '/%s/odom_out_and_back' % ns
        publishers, subscribers, _ = master.getSystemState()
        return any(node in nodes for _, nodes in publishers + subscribers)

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

        pending = set(namespaces)
        while pending and not rospy.is_shutdown():
            for ns in list(pending):
                if (tracks[ns].farthest > 0.5
                        and not self.course_running(master, ns)):
                    pending.discard(ns)
            self.assertLess(rospy.Time.now(), deadline,
                            'course not completed in %s: %s' % (
                                timeout.to_sec(), ' '.join(sorted(pending))))
            rospy.sleep(0.2)
        rospy.sleep(1.0)  # let the robots coast to a stop
        for ns, track in tracks.items():
            self.assertLess(track.end_distance(), max_end,
                            '%s: the course node exited %.2f m from the start:'
                            ' it aborted (see its log)' % (
                                ns, track.end_distance()))

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
