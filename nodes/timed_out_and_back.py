#!/usr/bin/env python3
"""timed_out_and_back.py - the book's out-and-back course, open loop on time.

Drives ~goal_distance at ~linear_speed for goal_distance / linear_speed
seconds, turns ~goal_angle at ~angular_speed for goal_angle / angular_speed
seconds, twice, with a pause after each move. Unlike the book, which counts
ticks as if every turn ran at 1 rad/s, each duration comes from the speeds
and is timed on ROS time, so the course also works at other speeds and
under simulated time. No odometry is needed to drive; if the odom -> base
transform exists it is watched (staleness stops the robot) and the summary
line gives the final pose. The course lives in rbx1_nav.motion.course.book, the
ROS side in rbx1_nav.motion.runner.runner_ros.

Publishes:  cmd_vel (geometry_msgs/Twist), relative.
Subscribes: odom (nav_msgs/Odometry), only its velocity: the summary counts the
            spells the robot stood still while commanded to move.
Parameters: the book's values by default; ~rate and every one after it
are the runner's (rbx1_nav.motion.runner.runner_params), shared by every motion node.
Exit status: 0 after a completed course, 1 otherwise; the robot is always
sent a stop.
"""

import signal

signal.signal(signal.SIGINT, signal.SIG_DFL)  # a signal during the imports: gone, quietly

from rbx1_nav.common.node_ros import exit_node  # noqa: E402
from rbx1_nav.entry.course_clock_ros import course_clock  # noqa: E402
from rbx1_nav.motion.course.book import TIMED_OUT_AND_BACK  # noqa: E402
from rbx1_nav.motion.runner.runner_params import common_params  # noqa: E402
from rbx1_nav.motion.runner.runner_ros import run_course_node  # noqa: E402

NAME = 'timed_out_and_back'
PARAMS = TIMED_OUT_AND_BACK.params + common_params(rate=TIMED_OUT_AND_BACK.rate)


if __name__ == '__main__':
    exit_node(NAME, run_course_node(NAME, PARAMS, TIMED_OUT_AND_BACK.build, course_clock,
                                    require_tf=False,
                                    doc=__doc__))
