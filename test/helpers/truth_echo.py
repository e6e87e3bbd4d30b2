#!/usr/bin/env python3
"""Print each robot's ground-truth pose whenever it changes: ``R x y yaw``.

Run on the robot host by test_two_hosts.py (argv: the robot namespaces),
so the test sees, in wall time, when each robot moved and when it stood
still, without a rostopic echo per robot.
"""
import sys
import threading

import rospy
from nav_msgs.msg import Odometry

from rbx1_nav.transform_utils import quat_to_angle


def main(robots):
    rospy.init_node('truth_echo')
    last = {}
    lock = threading.Lock()  # one whole line at a time from the callbacks

    def on_truth(msg, robot):
        p = msg.pose.pose
        row = '%.5f %.5f %.5f' % (p.position.x, p.position.y, quat_to_angle(p.orientation))
        with lock:
            if last.get(robot) != row:
                last[robot] = row
                sys.stdout.write('%s %s\n' % (robot, row))
                sys.stdout.flush()

    for robot in robots:
        rospy.Subscriber(robot + '/ground_truth', Odometry, on_truth, robot, queue_size=100)
    rospy.spin()


if __name__ == '__main__':
    main(rospy.myargv()[1:])
