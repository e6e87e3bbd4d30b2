"""Odometry calibration: the book's linear and angular scale tests
(calibrate_linear.py, calibrate_angular.py), UMBmark's bidirectional square,
and the simulator's ground truth as a tape measure.

``*_ros.py`` modules import rospy; the others do not.
"""
