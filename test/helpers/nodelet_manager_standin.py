#!/usr/bin/env python3
"""A stand-in for turtlebot_bringup's mobile_base_nodelet_manager: one process that takes the
robot's velocity topic as the driver does and publishes on it as the velocity multiplexer loaded
beside the driver does (cmd_vel_mux's inputs relayed to its output). Run it as
``mobile_base_nodelet_manager``; the robot it stands beside is the fake robot remapped to
``mobile_base/commands/velocity``, which acts on the commands. Nothing here is part of a
lockstep graph: it relays only what its inputs get, and the tests send it none."""
import rospy
from geometry_msgs.msg import Twist

OUTPUT = 'mobile_base/commands/velocity'
INPUTS = ('cmd_vel_mux/input/navi', 'cmd_vel_mux/input/teleop',
          'cmd_vel_mux/input/safety_controller')


def main():
    rospy.init_node('mobile_base_nodelet_manager')
    mux = rospy.Publisher(OUTPUT, Twist, queue_size=10)
    rospy.Subscriber(OUTPUT, Twist, lambda msg: None, queue_size=1)  # the driver's side
    for name in INPUTS:
        rospy.Subscriber(name, Twist, mux.publish, queue_size=10)
    rospy.spin()


if __name__ == '__main__':
    main()
