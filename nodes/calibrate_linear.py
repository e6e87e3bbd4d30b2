#!/usr/bin/env python3
"""calibrate_linear.py - find the driver's odom_linear_scale_correction.

The ROS By Example calibration: on start_test, drive ~test_distance on
odometry (tf odom -> base), let the robot settle, and compare what odometry
says with the distance measured on the floor (or ~ground_truth_topic).
Prints odom_linear_scale_correction = measured / odometry.

  rosrun rbx1_nav calibrate_linear.py _start_test:=true
  rosrun dynamic_reconfigure dynparam set /calibrate_linear measured_distance 0.97

Publishes:  cmd_vel (geometry_msgs/Twist), relative.
Subscribes: odom (its velocity, as every motion node) and, when set,
            ~ground_truth_topic (nav_msgs/Odometry).

The first six parameters below are the reconfigure fields
(rbx1_nav.cfg.CalibrateLinearConfig): dynparam sets them while the node
runs; the rest are read at start-up.
"""
import signal

signal.signal(signal.SIGINT, signal.SIG_DFL)  # a signal during the imports: gone, quietly

from rbx1_nav.calibration.scale import LINEAR  # noqa: E402
from rbx1_nav.cfg import CalibrateLinearConfig  # noqa: E402
from rbx1_nav.calibration.scale_ros import main, node_params  # noqa: E402
from rbx1_nav.common.node_ros import exit_node  # noqa: E402
from rbx1_nav.entry.course_clock_ros import course_clock  # noqa: E402

NAME = 'calibrate_linear'
PARAMS = node_params(CalibrateLinearConfig)

if __name__ == '__main__':
    exit_node(NAME, main(LINEAR, CalibrateLinearConfig, PARAMS, course_clock, __doc__))
