#!/usr/bin/env python3
"""Republish a fused pose (PoseWithCovarianceStamped) as nav_msgs/Odometry.

Subscribes ``input`` (geometry_msgs/PoseWithCovarianceStamped) and publishes
``output`` (nav_msgs/Odometry); ``launch/odom_ekf.launch`` remaps them to
``/robot_pose_ekf/odom_combined`` (where robot_pose_ekf and pose_ekf.py
publish) and ``/odom_ekf`` so RViz can show the gyro + wheel estimate next
to the raw ``/odom``. The mapping lives in ``rbx1_nav.estimation.odom_ekf``. Should
nothing come on the input within 5 s (wall time, SILENT) of start-up, one
warning names the topic and the topics that carry
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
import threading

import rospy
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry

from rbx1_nav.estimation.input_check import RejectedInput
from rbx1_nav.common.ros_time import time_moved_back_text
from rbx1_nav.estimation.odom_ekf import SENSOR, PoseToOdometry, silent_input_text
from rbx1_nav.common.params import POSITIVE, flag, frame, number, param
from rbx1_nav.common.master_ros import MasterWatch, reregister_node, topic_graph
from rbx1_nav.common.node_ros import start_node

SILENT = 5.0  # wall s without input before the warning
POSE_TYPE = 'geometry_msgs/PoseWithCovarianceStamped'

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
        self.input_topic = rospy.resolve_name('input')
        rospy.loginfo('odom_ekf: %s -> %s', self.input_topic,
                      rospy.resolve_name('output'))
        self.pub = rospy.Publisher('output', Odometry, queue_size=10)
        self.received = threading.Event()
        # Subscribe last so no callback runs before the publisher exists.
        self.sub = rospy.Subscriber('input', PoseWithCovarianceStamped,
                                    self.on_pose, queue_size=10)
        threading.Thread(target=self.check_input, daemon=True,
                         name='input_check').start()

    def check_input(self):
        """Warn once if nothing came on the input within SILENT s, naming
        who publishes it and the topics it could be remapped to."""
        if self.received.wait(SILENT) or rospy.is_shutdown():
            return
        publishers = candidates = None
        graph = topic_graph()  # with a timeout: an unreachable master blocks nothing
        if graph is not None:
            published, _, types = graph
            publishers = published.get(self.input_topic, [])
            candidates = [topic for topic, kind in types.items()
                          if kind == POSE_TYPE and published.get(topic)]
        rospy.logwarn('odom_ekf: ' + silent_input_text(
            self.input_topic, SILENT, publishers, candidates))

    def on_pose(self, msg):
        """Convert one fused pose and publish it; drop bad input with a warning."""
        self.received.set()
        now = rospy.Time.now().to_sec()
        back = self.converter.check_clock(now)
        if back > 0.0:
            rospy.logwarn('odom_ekf: ' + time_moved_back_text(back))
        try:
            odom = self.converter.convert(msg)
        except RejectedInput as err:
            text = self.converter.inputs.warning(
                err, now, '%s on %s' % (SENSOR, self.input_topic))
            if text:
                rospy.logwarn('odom_ekf: ' + text)
            return
        self.pub.publish(odom)


def main():
    values = start_node('odom_ekf', PARAMS, __doc__)
    if values is None:
        raise SystemExit(1)
    MasterWatch('odom_ekf', on_restarted=lambda uri: reregister_node(
        'odom_ekf', uri)).start()
    OdomEkfNode(values)
    rospy.spin()


if __name__ == '__main__':
    main()
