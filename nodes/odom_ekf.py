#!/usr/bin/env python3
"""Republish a fused pose (PoseWithCovarianceStamped) as nav_msgs/Odometry.

Subscribes ``input`` (geometry_msgs/PoseWithCovarianceStamped) and publishes
``output`` (nav_msgs/Odometry); ``launch/odom_ekf.launch`` remaps them to
``/odom_combined`` and ``/odom_ekf`` so RViz can show the gyro + wheel
estimate next to the raw ``/odom``. The mapping lives in
``rbx1_nav.odom_ekf``.

Private parameters:
  ~frame_id (str, ''): output frame; empty keeps the input's frame.
  ~child_frame_id (str, 'base_footprint'): the robot's base frame.
  ~estimate_twist (bool, true): twist from successive poses, else zero and
      marked unknown.
  ~twist_variance (float, 0.01): variance given to an estimated twist.
A bad parameter is logged and the node exits with status 1.
"""
import rospy
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry

from rbx1_nav.odom_ekf import PoseToOdometry
from rbx1_nav.params import POSITIVE, flag, frame, number, param
from rbx1_nav.ros.node import start_node

PARAMS = (
    param('frame_id', '', frame, '', "output frame; '' keeps the input's",
          allow_empty=True),
    param('child_frame_id', 'base_footprint', frame, '', "the robot's base frame"),
    param('estimate_twist', True, flag, '',
          'twist from successive poses, else zero and marked unknown'),
    param('twist_variance', 0.01, number, '',
          'variance given to an estimated twist', **POSITIVE),
)


class OdomEkfNode(object):
    """Wires ``input`` -> PoseToOdometry -> ``output``."""

    def __init__(self, values):
        self.converter = PoseToOdometry(**values)
        rospy.loginfo('odom_ekf: %s -> %s', rospy.resolve_name('input'),
                      rospy.resolve_name('output'))
        self.pub = rospy.Publisher('output', Odometry, queue_size=10)
        # Subscribe last so no callback runs before the publisher exists.
        self.sub = rospy.Subscriber('input', PoseWithCovarianceStamped,
                                    self.on_pose, queue_size=10)

    def on_pose(self, msg):
        """Convert one fused pose and publish it; drop bad input with a warning."""
        try:
            odom = self.converter.convert(msg)
        except ValueError as err:
            rospy.logwarn_throttle(5.0, 'odom_ekf: dropped a pose: %s' % err)
            return
        self.pub.publish(odom)


def main():
    values = start_node('odom_ekf', PARAMS, __doc__)
    if values is None:
        raise SystemExit(1)
    OdomEkfNode(values)
    rospy.spin()


if __name__ == '__main__':
    main()
