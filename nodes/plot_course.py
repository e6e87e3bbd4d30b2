#!/usr/bin/env python3
"""plot_course.py - plot an out-and-back run recorded in a bag.

    rosrun rbx1_nav plot_course.py course.bag [-o course.png]

Draws the odometry path (nav_msgs/Odometry on odom) and, when the bag has
them, the simulator's true path (ground_truth) and pose_ekf's fused path
(geometry_msgs/PoseWithCovarianceStamped on robot_pose_ekf/odom_combined),
with start and end poses and the end-vs-start error in the title. A bag
from a real robot, with odom only, works too. With a fused path and a true
path, the title also gives each path's final distance from the truth.
Record one with
``roslaunch rbx1_nav odom_out_and_back_sim.launch record:=true``; fuse it
again with ``roslaunch rbx1_nav pose_ekf_replay.launch bag:=course.bag
record:=true out:=fused.bag`` and plot ``fused.bag``. No ROS master is needed.
"""
import sys

from rbx1_nav.motion.plot.course_plot_ros import main

if __name__ == '__main__':
    sys.exit(main(__doc__))
