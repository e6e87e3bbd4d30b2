#!/usr/bin/env python3
"""Republish a fused pose (PoseWithCovarianceStamped) as nav_msgs/Odometry.

Subscribes the fused pose (geometry_msgs/PoseWithCovarianceStamped) and
publishes it as ``output`` (nav_msgs/Odometry; ``launch/odom_ekf.launch``
remaps it to ``/odom_ekf``) so RViz can show the gyro + wheel estimate next
to the raw ``/odom``. Unless ``input`` is remapped (then that topic alone),
it hears both ``odom_combined``, the book's name (a TurtleBot's bringup
remaps robot_pose_ekf's output there), and ``robot_pose_ekf/odom_combined``,
where robot_pose_ekf and pose_ekf.py publish it, and follows the first that
delivers a pose. Should the other deliver too, its poses are dropped with
one warning naming both topics and the remap that follows the other; the
node follows the other only once the first has been silent for 5 s (wall
time). The mapping and the choice live in ``rbx1_nav.estimation.odom_ekf``.
Should nothing come on the input within 5 s (wall time, SILENT) of
start-up, one warning names the topics and the topics that carry
PoseWithCovarianceStamped.

A bad parameter is logged and the node exits with status 1. Unstamped,
out-of-order or repeated poses, NaN or absurd values and negative variances
are dropped, with one warning per kind every 10 s that counts them, so the
output's stamps only move forward. Should ROS time move backwards (a bag
looping, a simulator restarted) the node says so and takes the poses of the
new clock. Should the ROS master restart, the node says so within a few
seconds and registers its topics with the new master, so RViz and new
nodes find them again (rbx1_nav.common.master_ros); its connections go on.
"""
import signal

signal.signal(signal.SIGINT, signal.SIG_DFL)  # a signal during the imports: gone, quietly

from rbx1_nav.common.node_ros import exit_node  # noqa: E402
from rbx1_nav.common.params import POSITIVE, flag, frame, number, param  # noqa: E402
from rbx1_nav.estimation.odom_ekf_ros import main  # noqa: E402

NAME = 'odom_ekf'

PARAMS = (
    param('frame_id', '', frame, '', "output frame; '' keeps the input's",
          allow_empty=True),
    param('child_frame_id', 'base_footprint', frame, '', "the robot's base frame"),
    param('estimate_twist', True, flag, '',
          'twist from successive poses, else zero and marked unknown'),
    param('twist_variance', 0.01, number, '',
          'variance given to an estimated twist', **POSITIVE),
)


if __name__ == '__main__':
    exit_node(NAME, main(PARAMS, __doc__))
