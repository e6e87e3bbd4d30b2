#!/usr/bin/env python3
"""fake_fleet: N fake TurtleBots in one process.

Each robot named in ~robots is what fake_turtlebot.py is in that namespace,
with the same parameters for every robot; the model steps all of them in
numpy arrays (rbx1_nav.sim.diff_drive.DiffDriveFleet), or with ~physics in one
MuJoCo model (rbx1_nav.sim.physics.PhysicsFleet), so N robots cost one
process. `roslaunch rbx1_nav fleet.launch n:=10` starts one with robot1 ..
robot10.

For each robot R in ~robots (names relative to this node's namespace):
Subscribes:  R/cmd_vel (geometry_msgs/Twist)
Publishes:   R/odom, R/ground_truth (nav_msgs/Odometry), R/joint_states,
             R/imu_data (if ~publish_imu), R/gps (if ~publish_gps); the tf
             R/odom_frame -> R/base_frame on R/tf and the static
             ground_truth_frame -> R/odom_frame on R/tf_static: each robot's
             transforms on its own topic, so a listener there (remap /tf:=tf
             in the robot's namespace) receives no other robot's.
Frames:      R/ before ~odom_frame, ~base_frame and ~imu_frame (robot1/odom,
             robot1/base_footprint); ~ground_truth_frame (world) is shared.
Parameters:  ~robots and every parameter of fake_turtlebot.py
             (rbx1_nav.sim.params; --help lists them). A bad value is logged
             and the node exits with status 1. Noise comes from one
             generator for the fleet (seeded by ~seed), each robot's GPS
             from its own.
"""
import signal

signal.signal(signal.SIGINT, signal.SIG_DFL)  # a signal during the imports: gone, quietly

from rbx1_nav.common.node_ros import exit_node  # noqa: E402
from rbx1_nav.sim.node_ros import fake_fleet  # noqa: E402
from rbx1_nav.sim.params import PARAMS as ROBOT_PARAMS, ROBOTS  # noqa: E402

PARAMS = (ROBOTS,) + ROBOT_PARAMS

NAME = 'fake_fleet'

if __name__ == '__main__':
    exit_node(NAME, fake_fleet(PARAMS, __doc__))
