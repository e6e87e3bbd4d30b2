#!/usr/bin/env python3
"""rostest: GPS fusion ends the course closer to the truth than odometry + gyro.

pose_ekf_gps.test drives the realistic fake robot over a 20 m course while
two pose_ekf nodes estimate its pose: one from odometry and the gyro, one
with GPS too. When the course node has exited, this test compares each estimate's
position ~settle_time simulated seconds after the robot came to rest (by
the messages' stamps: the same on every run) with the simulator's ground
truth, prints both errors and asserts the ratio.

At rest the GPS-fused position is the average of the fixes since the robot
stopped, in the GPS frame (robot_pose_ekf's gps_used mode), so its error is
that average's: about gps_noise / sqrt(fixes). ~settle_time must give enough
fixes for the limit to hold by design, not by a lucky draw of the noise.
"""
import bisect
import math
import os
import sys
import threading
import unittest

import rosgraph
import rospy
import rostest
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import MASTER_POLL, node_registered  # noqa: E402


class Track(object):
    """Every position on a topic by its stamp, with the farthest excursion seen."""

    def __init__(self, topic, msg_type):
        self.lock = threading.Lock()
        self.stamps, self.positions = [], []
        self.farthest = 0.0
        rospy.Subscriber(topic, msg_type, self.on_msg, queue_size=50)

    @property
    def count(self):
        return len(self.stamps)

    def on_msg(self, msg):
        p = msg.pose.pose.position
        with self.lock:
            self.stamps.append(msg.header.stamp.to_nsec())
            self.positions.append((p.x, p.y))
            first = self.positions[0]
            self.farthest = max(self.farthest, math.hypot(p.x - first[0], p.y - first[1]))

    def came_to_rest(self):
        """The stamp (ns) from which the position no longer changed."""
        with self.lock:
            moved = [i for i in range(1, len(self.positions))
                     if self.positions[i] != self.positions[i - 1]]
            return self.stamps[moved[-1] if moved else 0]

    def position_at(self, stamp):
        """The newest position stamped at or before ``stamp`` (ns): under
        lockstep the same on every run, however late this test looks."""
        with self.lock:
            return self.positions[bisect.bisect_right(self.stamps, stamp) - 1]


class PoseEkfGpsTest(unittest.TestCase):

    def test_gps_fused_pose_ends_closer_to_the_truth(self):
        timeout = rospy.Duration(float(rospy.get_param('~timeout')))
        max_ratio = float(rospy.get_param('~max_error_ratio'))
        min_excursion = float(rospy.get_param('~min_excursion'))
        course = rospy.resolve_name(rospy.get_param('~course_node'))
        truth = Track('ground_truth', Odometry)
        raw = Track(rospy.get_param('~raw_topic'), PoseWithCovarianceStamped)
        fused = Track(rospy.get_param('~fused_topic'), PoseWithCovarianceStamped)
        master = rosgraph.Master(rospy.get_name())
        deadline = rospy.Time.now() + timeout
        while not truth.count or not node_registered(master, course):
            self.assertLess(rospy.Time.now(), deadline,
                            'no ground_truth or no course node')
            rospy.rostime.wallsleep(MASTER_POLL)
        while node_registered(master, course) and not rospy.is_shutdown():
            self.assertLess(rospy.Time.now(), deadline,
                            'course not completed in %.0f s' % timeout.to_sec())
            rospy.rostime.wallsleep(MASTER_POLL)
        # The robot stops; at rest the GPS fixes keep refining the fused pose.
        # Each estimate is read ~settle_time simulated s after the robot came to
        # rest, by its stamp: when this test sees the course gone is wall-timed.
        settled = truth.came_to_rest() + int(float(rospy.get_param('~settle_time')) * 1e9)
        rospy.sleep(rospy.Time(0, settled) + rospy.Duration(1.0) - rospy.Time.now())
        self.assertGreater(truth.farthest, min_excursion,
                           'the robot hardly moved: the course aborted')
        self.assertTrue(raw.count and fused.count, 'no odom_combined')
        tx, ty = truth.position_at(settled)
        errors = {}
        for name, track in (('odometry + gyro', raw), ('with GPS', fused)):
            x, y = track.position_at(settled)
            errors[name] = math.hypot(x - tx, y - ty)
        report = ('final position error against ground truth, the robot '
                  '%.1f m from its start: odometry + gyro %.3f m, with GPS '
                  '%.3f m (ratio %.2f)' % (
                      truth.farthest, errors['odometry + gyro'],
                      errors['with GPS'],
                      errors['with GPS'] / max(errors['odometry + gyro'],
                                               1e-9)))
        print(report, flush=True)
        rospy.loginfo(report)
        self.assertLess(errors['with GPS'],
                        max_ratio * errors['odometry + gyro'],
                        report + '; want with GPS < %.3f x odometry + gyro'
                        % max_ratio)


if __name__ == '__main__':
    rospy.init_node('pose_ekf_gps_test')
    rostest.rosrun('rbx1_nav', 'pose_ekf_gps', PoseEkfGpsTest)
