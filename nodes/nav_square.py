#!/usr/bin/env python3
"""nav_square.py - drive a square measured by odometry via tf2.

The ROS By Example square: [drive ~goal_distance, turn ~goal_angle] x 4,
closed loop on the odom -> base transform. As in the book each turn stops
once the turned angle plus ~angular_tolerance reaches ~goal_angle, so with
the defaults every corner may come up to 2 degrees short; ~precise slows
down near each goal instead and ends within millimetres. Unlike the book's
node, ~odom_frame and ~base_frame are honoured.

Publishes:  cmd_vel (geometry_msgs/Twist), relative.
Subscribes: odom (nav_msgs/Odometry), only its velocity: the summary counts the
            spells the robot stood still while commanded to move.
Parameters: the book's values by default; the last seven are the
runner's (rbx1_nav.motion.runner_ros), shared by every motion node.
Exit status: 0 after a completed square, 1 otherwise; the robot is always
sent a stop.
"""
import math

from rbx1_nav.motion.course import Course, legs_course, legs_params
from rbx1_nav.motion.precise import PRECISE_PARAMS, approach
from rbx1_nav.common.node_ros import exit_node
from rbx1_nav.motion.runner_ros import common_params, run_course_node

NAME = 'nav_square'
SIDES = 4
PARAMS = legs_params(linear_speed=0.2, goal_distance=1.0, angular_speed=0.7,
                     goal_angle=90.0, angle_unit='deg', angular_tolerance=2.0,
                     pause=1.0) + PRECISE_PARAMS + common_params(rate=20.0)


def build_course(values):
    return Course(legs_course(
        values['goal_distance'], math.radians(values['goal_angle']), SIDES,
        values['linear_speed'], values['angular_speed'],
        math.radians(values['angular_tolerance']), values['pause'],
        approach(values)))


if __name__ == '__main__':
    exit_node(NAME, run_course_node(NAME, PARAMS, build_course, doc=__doc__))
