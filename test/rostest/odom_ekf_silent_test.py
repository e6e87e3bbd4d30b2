#!/usr/bin/env python3
"""rostest: odom_ekf names a silent input and the topic to remap it to.

Run by odom_ekf_silent.test: odom_ekf.launch listens on /odom_combined
(the book's name) and /robot_pose_ekf/odom_combined (where
robot_pose_ekf and pose_ekf.py publish) while the only fused pose is on
/my_filter/pose. Within odom_ekf's SILENT s (plus start-up) one warning
must name all three. The node goes on after it: poses that then come on
/odom_combined (a filter started late) come out on /odom_ekf, each with its
stamp and position, and Ctrl-C ends it with status 0.
"""
import os
import signal
import sys
import threading
import unittest
import xmlrpc.client

import rosgraph
import rosnode
import rospy
import rostest
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import RosoutWatch, launched_node_status, wait_until  # noqa: E402

NODE = '/odom_ekf'
LATE_POSES = 20  # poses published on /odom_combined after the warning, at 10 Hz


class OdomEkfSilentTest(unittest.TestCase):

    def test_a_silent_input_is_named_with_the_topic_to_remap_to(self):
        log = RosoutWatch()
        lock = threading.Lock()
        out = []

        def on_output(msg):
            with lock:
                out.append((msg.header.stamp, msg.pose.pose.position.x))

        rospy.Subscriber('/odom_ekf', Odometry, on_output)
        self.assertTrue(wait_until(lambda: log.find(NODE, 'nothing on'),
                                   wall_limit=30.0), 'no warning from odom_ekf')
        line = log.find(NODE, 'nothing on').msg
        print('RESULT odom_ekf silent input: %r' % line)
        self.assertIn('nothing on /odom_combined or '
                      '/robot_pose_ekf/odom_combined after 5 s', line)
        self.assertIn('input:=/my_filter/pose', line)
        # It goes on: each pose that comes now on /odom_combined comes out
        # on /odom_ekf, the same stamp and x (0.1 m apart from one to the next).
        # (Its publisher only now: one before would change the warning.)
        late = rospy.Publisher('/odom_combined', PoseWithCovarianceStamped,
                               queue_size=LATE_POSES)
        self.assertTrue(wait_until(lambda: late.get_num_connections() > 0, 10.0),
                        'odom_ekf does not subscribe /odom_combined')
        sent = []
        for k in range(LATE_POSES):
            msg = PoseWithCovarianceStamped()
            msg.header.stamp, msg.header.frame_id = rospy.Time.now(), 'odom'
            msg.pose.pose.position.x = 0.1 * k
            msg.pose.pose.orientation.w = 1.0
            late.publish(msg)
            sent.append((msg.header.stamp, msg.pose.pose.position.x))
            rospy.rostime.wallsleep(0.1)
        wait_until(lambda: len(out) >= LATE_POSES, wall_limit=10.0)
        with lock:
            got = list(out)
        print('RESULT after the warning: %d of %d poses came out on /odom_ekf'
              % (len(got), LATE_POSES))
        self.assertEqual([stamp for stamp, _ in got], [stamp for stamp, _ in sent])
        for (_, x_out), (_, x_in) in zip(got, sent):
            self.assertAlmostEqual(x_out, x_in, delta=1e-9)
        # Ctrl-C, as a user at the terminal of odom_ekf.launch.
        uri = rosnode.get_api_uri(rosgraph.Master(rospy.get_name()), NODE,
                                  skip_cache=True)
        pid = xmlrpc.client.ServerProxy(uri).getPid(rospy.get_name())[2]
        os.kill(pid, signal.SIGINT)
        status, node_log = launched_node_status('odom_ekf', wall_limit=30.0)
        print('RESULT odom_ekf exit status on SIGINT: %s' % status)
        self.assertEqual(status, 0, node_log)


if __name__ == '__main__':
    rospy.init_node('odom_ekf_silent_test')
    rostest.rosrun('rbx1_nav', 'odom_ekf_silent', OdomEkfSilentTest)
