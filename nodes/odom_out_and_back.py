#!/usr/bin/env python3
"""odom_out_and_back.py - drive 1 m out and back, measured by odometry via tf2.

The ROS By Example course: [drive ~goal_distance, turn ~goal_angle] x ~legs,
closed loop on the odom -> base transform. The course lives in
rbx1_nav.out_and_back, the ROS side in rbx1_nav.ros.runner.

Publishes:  cmd_vel (geometry_msgs/Twist), relative, so a namespace works.
Subscribes: odom (nav_msgs/Odometry), only its velocity: the summary counts the
            spells the robot stood still while commanded to move.
Parameters (private, book's values by default):
  ~linear_speed 0.15 m/s   ~goal_distance 1.0 m   ~angular_speed 0.5 rad/s
  ~goal_angle pi rad       ~angular_tolerance 1.0 deg   ~rate 20 Hz
  ~legs 2                  ~pause 1.0 s           ~precise false
  ~precise_gain 1.0 /s     ~precise_heading_gain 4.0 /s
  ~precise_min_linear_speed 0.005 m/s   ~precise_min_angular_speed 0.01 rad/s
  ~odom_frame odom         ~base_frame '' (try base_footprint, then base_link)
  ~tf_wait 5.0 s (for the first transform)   ~tf_timeout 1.0 s (staleness)
  ~start_delay 0.0 s (pause before moving, e.g. to let a bag recorder start)
Exit status: 0 after a completed course, 1 on bad parameters, missing or
stale tf, an error or an interruption. The robot is always sent a stop.
"""
import math

from rbx1_nav.motion import PRECISE_PARAMS, legs_params
from rbx1_nav.out_and_back import CourseConfig, OutAndBack
from rbx1_nav.ros.node import exit_node
from rbx1_nav.ros.runner import common_params, run_course_node

NAME = 'odom_out_and_back'
PARAMS = legs_params(linear_speed=0.15, goal_distance=1.0, angular_speed=0.5,
                     goal_angle=math.pi, angular_tolerance=1.0, legs=2,
                     pause=1.0) + PRECISE_PARAMS
COURSE = tuple(p.name for p in PARAMS)
PARAMS += common_params(rate=20.0)


def build_course(values):
    settings = {name: values[name] for name in COURSE}
    settings['angular_tolerance'] = math.radians(values['angular_tolerance'])
    return OutAndBack(CourseConfig(**settings))


if __name__ == '__main__':
    exit_node(NAME, run_course_node(NAME, PARAMS, build_course, doc=__doc__))
