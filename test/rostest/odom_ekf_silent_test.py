#!/usr/bin/env python3
"""rostest: odom_ekf names a silent input and the topic to remap it to.

Run by odom_ekf_silent.test: odom_ekf.launch listens on /odom_combined
(the book's name) and /robot_pose_ekf/odom_combined (where
robot_pose_ekf and pose_ekf.py publish) while the only fused pose is on
/my_filter/pose. Within odom_ekf's SILENT s (plus start-up) one warning
must name all three.
"""
import os
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import RosoutWatch, wait_until  # noqa: E402


class OdomEkfSilentTest(unittest.TestCase):

    def test_a_silent_input_is_named_with_the_topic_to_remap_to(self):
        log = RosoutWatch()
        self.assertTrue(wait_until(lambda: log.find('/odom_ekf', 'nothing on'),
                                   wall_limit=30.0), 'no warning from odom_ekf')
        line = log.find('/odom_ekf', 'nothing on').msg
        print('RESULT odom_ekf silent input: %r' % line)
        self.assertIn('nothing on /odom_combined or '
                      '/robot_pose_ekf/odom_combined after 5 s', line)
        self.assertIn('input:=/my_filter/pose', line)


if __name__ == '__main__':
    rospy.init_node('odom_ekf_silent_test')
    rostest.rosrun('rbx1_nav', 'odom_ekf_silent', OdomEkfSilentTest)
