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
Parameters:  rbx1_nav.sim.params.PARAMS (--help lists them), every field
             of rbx1_nav.sim.diff_drive.DiffDriveConfig among them (bounds in
             its CONFIG_LIMITS) and, with ~physics, of
             rbx1_nav.sim.physics.PhysicsConfig. A bad value (or ~physics
             without MuJoCo installed) is logged and the node exits with
             status 1.
The topics are rbx1_nav.sim.robot_ros.RobotTopics, shared with
fake_fleet.py (N robots in one process).
"""
import threading

import rospy

from rbx1_nav.sim.params import PARAMS
from rbx1_nav.sim.robot_ros import RobotTopics, make_fleet, spin_simulator
from rbx1_nav.common.node_ros import start_node, until_shutdown


class FakeTurtleBot:
    """The model (a fleet of one), its topics (RobotTopics) and the
    fixed-rate loop."""

    def __init__(self, values):
        self.rate = values['rate']
        self.sim = make_fleet(values, 1, 'fake_turtlebot')
        self.lock = threading.Lock()
        self.topics = RobotTopics(self.sim.robot(0), values, self.lock)

    def spin(self):
        """Step the model on a fixed grid of ROS times (under lockstep, also
        at its motion nodes' ticks) and publish each step: see
        rbx1_nav.sim.robot_ros.spin_simulator."""
        spin_simulator(self.rate, self.step, [self.topics], 'fake_turtlebot')

    def step(self, stamp):
        """Advance the model to ``stamp`` and publish the new state."""
        with self.lock:
            advanced = self.sim.step(stamp.to_sec())
        if advanced:
            self.topics.publish(stamp)


def main():
    values = start_node('fake_turtlebot', PARAMS, __doc__)
    if values is None:
        raise SystemExit(1)
    try:
        robot = FakeTurtleBot(values)
    except (ValueError, ImportError) as err:
        rospy.logfatal('fake_turtlebot: %s', err)
        raise SystemExit(1)
    until_shutdown(robot.spin)


if __name__ == '__main__':
    main()
