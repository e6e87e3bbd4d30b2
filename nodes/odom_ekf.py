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
from rbx1_nav.params import flag, frame, number


def param(name, default, check, **options):
    """Parameter ``name`` checked by a rbx1_nav.params function."""
    return check(name, rospy.get_param(name, default), **options)


class OdomEkfNode(object):
    """Wires ``input`` -> PoseToOdometry -> ``output``."""

    def __init__(self):
        self.converter = PoseToOdometry(
            frame_id=param('~frame_id', '', frame, allow_empty=True),
            child_frame_id=param('~child_frame_id', 'base_footprint', frame),
            estimate_twist=param('~estimate_twist', True, flag),
            twist_variance=param('~twist_variance', 0.01, number,
                                 minimum=0.0, allow_zero=False))
        rospy.loginfo('odom_ekf: frame_id=%r child_frame_id=%r '
                      'estimate_twist=%s twist_variance=%g; %s -> %s',
                      self.converter.frame_id or '(from input)',
                      self.converter.child_frame_id,
                      self.converter.estimate_twist,
                      self.converter.twist_variance,
                      rospy.resolve_name('input'), rospy.resolve_name('output'))
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
    rospy.init_node('odom_ekf')
    try:
        OdomEkfNode()
    except ValueError as err:
        rospy.logfatal('odom_ekf: %s' % err)
        raise SystemExit(1)
    rospy.spin()


if __name__ == '__main__':
    main()
