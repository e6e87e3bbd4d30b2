#!/usr/bin/env python3
"""calibrate_angular.py - find the driver's odom_angular_scale_correction.

The ROS By Example calibration: on start_test, turn ~test_angle on odometry
(tf odom -> base), let the robot settle, and compare what odometry says
with the angle really turned (measured on the floor, or from
~ground_truth_topic). Prints odom_angular_scale_correction = measured /
odometry.

  rosrun rbx1_nav calibrate_angular.py _start_test:=true
  rosrun dynamic_reconfigure dynparam set /calibrate_angular measured_angle 352

Publishes:  cmd_vel (geometry_msgs/Twist), relative.
Subscribes: odom (its velocity, as every motion node) and, when set,
            ~ground_truth_topic (nav_msgs/Odometry).

The first six parameters below are the reconfigure fields
(rbx1_nav.cfg.CalibrateAngularConfig): dynparam sets them while the node
runs; the rest are read at start-up.
"""
import signal

signal.signal(signal.SIGINT, signal.SIG_DFL)  # a signal during the imports: gone, quietly

from rbx1_nav.calibration.scale import ANGULAR  # noqa: E402
from rbx1_nav.cfg import CalibrateAngularConfig  # noqa: E402
from rbx1_nav.calibration.scale_ros import main, node_params  # noqa: E402
from rbx1_nav.common.node_ros import exit_node  # noqa: E402
from rbx1_nav.entry.course_clock_ros import course_clock  # noqa: E402

NAME = 'calibrate_angular'
PARAMS = node_params(CalibrateAngularConfig)

if __name__ == '__main__':
    exit_node(NAME, main(ANGULAR, CalibrateAngularConfig, PARAMS, course_clock, __doc__))
