#!/usr/bin/env python3
"""odom_out_and_back.py - drive 1 m out and back, measured by odometry via tf2.

The ROS By Example course: [drive ~goal_distance, turn ~goal_angle] x ~legs,
closed loop on the odom -> base transform. The course lives in
rbx1_nav.motion.course.book, the ROS side in rbx1_nav.motion.runner.runner_ros.

Publishes:  cmd_vel (geometry_msgs/Twist), relative, so a namespace works.
Subscribes: odom (nav_msgs/Odometry), only its velocity: the summary counts the
            spells the robot stood still while commanded to move.
Parameters: the book's values by default; ~rate and every one after it
are the runner's (rbx1_nav.motion.runner.runner_params), shared by every motion node.
Exit status: 0 after a completed course, 1 on bad or unknown parameters,
missing or stale tf, another node driving the robot, a transform from two
nodes or jumping further than the robot moves, an error or an
interruption. The robot is always sent a stop.
"""

import signal

signal.signal(signal.SIGINT, signal.SIG_DFL)  # a signal during the imports: gone, quietly

from rbx1_nav.common.node_ros import exit_node  # noqa: E402
from rbx1_nav.entry.course_clock_ros import course_clock  # noqa: E402
from rbx1_nav.motion.course.book import OUT_AND_BACK  # noqa: E402
from rbx1_nav.motion.runner.runner_params import common_params  # noqa: E402
from rbx1_nav.motion.runner.runner_ros import run_course_node  # noqa: E402

NAME = 'odom_out_and_back'
PARAMS = OUT_AND_BACK.params + common_params(rate=OUT_AND_BACK.rate)


if __name__ == '__main__':
    exit_node(NAME, run_course_node(NAME, PARAMS, OUT_AND_BACK.build, course_clock,
                                    doc=__doc__))
