#!/usr/bin/env python3
"""Print each robot's ground-truth pose whenever it changes: ``R x y yaw``.

Run on the robot host by test_two_hosts.py (argv: the robot namespaces),
so the test sees, in wall time, when each robot moved and when it stood
still, without a rostopic echo per robot. ``--topic NAME`` echoes another
nav_msgs/Odometry topic of each robot instead (test_rviz_views.py: odom);
with no namespace, the top-level topic, printed as robot ``/``.
"""
import sys
import threading

import rospy
from nav_msgs.msg import Odometry

from rbx1_nav.transform_utils import quat_to_angle


def main(args):
    topic = 'ground_truth'
    if args[:1] == ['--topic']:
        topic, args = args[1], args[2:]
    robots = args or ['']
    rospy.init_node('truth_echo' if topic == 'ground_truth' else topic + '_echo')
    last = {}
    lock = threading.Lock()  # one whole line at a time from the callbacks

    def on_truth(msg, robot):
        p = msg.pose.pose
        row = '%.5f %.5f %.5f' % (p.position.x, p.position.y, quat_to_angle(p.orientation))
        with lock:
            if last.get(robot) != row:
                last[robot] = row
                sys.stdout.write('%s %s\n' % (robot or '/', row))
                sys.stdout.flush()

    for robot in robots:
        rospy.Subscriber(robot + '/' + topic, Odometry, on_truth, robot, queue_size=100)
    rospy.spin()


if __name__ == '__main__':
    main(rospy.myargv()[1:])
