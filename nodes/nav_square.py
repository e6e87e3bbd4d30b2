#!/usr/bin/env python3
"""nav_square.py - drive a square measured by odometry via tf2.

The ROS By Example square: [drive ~goal_distance, turn ~goal_angle] x 4,
closed loop on the odom -> base transform. As in the book each turn stops
once the turned angle plus ~angular_tolerance reaches ~goal_angle, so with
the defaults every corner may come up to 2 degrees short; ~precise slows
down near each goal instead and ends within millimetres. Unlike the book's
node, ~odom_frame and ~base_frame are honoured. The course lives in
rbx1_nav.motion.course.book, the ROS side in rbx1_nav.motion.runner.runner_ros.

Publishes:  cmd_vel (geometry_msgs/Twist), relative.
Subscribes: odom (nav_msgs/Odometry), only its velocity: the summary counts the
            spells the robot stood still while commanded to move.
Parameters: the book's values by default; ~rate and every one after it
are the runner's (rbx1_nav.motion.runner.runner_params), shared by every motion node.
Exit status: 0 after a completed square, 1 otherwise; the robot is always
sent a stop.
"""

import signal

signal.signal(signal.SIGINT, signal.SIG_DFL)  # a signal during the imports: gone, quietly

from rbx1_nav.common.node_ros import exit_node  # noqa: E402
from rbx1_nav.entry.course_clock_ros import course_clock  # noqa: E402
from rbx1_nav.motion.course.book import NAV_SQUARE  # noqa: E402
from rbx1_nav.motion.runner.runner_params import common_params  # noqa: E402
from rbx1_nav.motion.runner.runner_ros import run_course_node  # noqa: E402

NAME = 'nav_square'
PARAMS = NAV_SQUARE.params + common_params(rate=NAV_SQUARE.rate)


if __name__ == '__main__':
    exit_node(NAME, run_course_node(NAME, PARAMS, NAV_SQUARE.build, course_clock,
                                    doc=__doc__))
