#!/usr/bin/env python3
"""fake_turtlebot: a kinematic TurtleBot base for simulation and tests.

A drop-in for the ArbotiX fake robot of ROS By Example. The motion model is
rbx1_nav.sim.diff_drive (kinematic: the base moves exactly as commanded) or,
with ~physics, rbx1_nav.sim.physics (real dynamics on MuJoCo: inertia,
motor torque and deadband, wheel slip, encoder ticks, a floor); this node
only reads parameters and wires the model to ROS.

Subscribes:  cmd_vel (geometry_msgs/Twist)
Publishes:   odom (nav_msgs/Odometry), tf odom_frame -> base_frame, static
             tf ground_truth_frame -> odom_frame (identity: odometry and
             the truth start together, so RViz shows both),
             joint_states (sensor_msgs/JointState), ground_truth
             (nav_msgs/Odometry), imu_data (sensor_msgs/Imu, if ~publish_imu),
             gps (nav_msgs/Odometry, if ~publish_gps: the true x, y in
             ~ground_truth_frame plus white noise of ~gps_noise m (1 sigma),
             at ~gps_rate Hz, with variance ~gps_noise^2; seeded by ~seed)
Lockstep:    under /lockstep, subscribes /lockstep_grant and publishes
             /lockstep_report (rbx1_nav.sim_time.member_ros)
Parameters:  rbx1_nav.sim.params.PARAMS (--help lists them), every field
             of rbx1_nav.sim.diff_drive.DiffDriveConfig among them (bounds in
             rbx1_nav.sim.params) and, with ~physics, of
             rbx1_nav.sim.physics.PhysicsConfig. A bad value (or ~physics
             without MuJoCo installed) is logged and the node exits with
             status 1.
The topics are rbx1_nav.sim.topics_ros.RobotTopics, shared with
fake_fleet.py (N robots in one process).
"""
import signal

signal.signal(signal.SIGINT, signal.SIG_DFL)  # a signal during the imports: gone, quietly

from rbx1_nav.common.node_ros import exit_node  # noqa: E402
from rbx1_nav.sim.node_ros import fake_turtlebot  # noqa: E402
from rbx1_nav.sim.params import PARAMS  # noqa: E402

NAME = 'fake_turtlebot'

if __name__ == '__main__':
    exit_node(NAME, fake_turtlebot(PARAMS, __doc__))
