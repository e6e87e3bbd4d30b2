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
import threading

import rospy

from rbx1_nav.sim import params as sim_params
from rbx1_nav.sim.robot_ros import RobotTopics, make_fleet, spin_simulator
from rbx1_nav.common.node_ros import start_node, until_shutdown

NAME = 'fake_fleet'
PARAMS = (sim_params.ROBOTS,) + sim_params.PARAMS


class FakeFleet:
    """The model (DiffDriveFleet, or PhysicsFleet with ~physics), one
    RobotTopics per robot, and the fixed-rate loop."""

    def __init__(self, values):
        self.rate = values['rate']
        self.names = values['robots']
        self.sim = make_fleet(values, len(self.names), NAME)
        self.lock = threading.Lock()
        self.robots = [RobotTopics(self.sim.robot(i), values, self.lock, ns=name,
                                   index=i, log_name='%s: %s' % (NAME, name))
                       for i, name in enumerate(self.names)]
        rospy.loginfo('%s: %d robots (%s), each with its tf on its own topic: '
                      '%s', NAME, len(self.names), ', '.join(self.names),
                      rospy.resolve_name(self.names[0] + '/tf'))

    def spin(self):
        """Step every robot on a fixed grid of ROS times (under lockstep,
        also at their motion nodes' ticks): see
        rbx1_nav.sim.robot_ros.spin_simulator."""
        spin_simulator(self.rate, self.step, self.robots, NAME)

    def step(self, stamp):
        """Advance every robot to ``stamp`` and publish their new states."""
        with self.lock:
            advanced = self.sim.step(stamp.to_sec())
        if advanced:
            for robot in self.robots:
                robot.publish(stamp)


def main():
    values = start_node(NAME, PARAMS, __doc__)
    if values is None:
        raise SystemExit(1)
    try:
        fleet = FakeFleet(values)
    except (ValueError, ImportError) as err:
        rospy.logfatal('%s: %s', NAME, err)
        raise SystemExit(1)
    until_shutdown(fleet.spin)


if __name__ == '__main__':
    main()
