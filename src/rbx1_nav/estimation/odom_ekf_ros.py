"""The ROS side of odom_ekf.py: ``input`` ->
:class:`rbx1_nav.estimation.odom_ekf.PoseToOdometry` -> ``output``, the
warning when the input stays silent, and re-registration after a master
restart.

The node file declares the parameters and calls :func:`main`.
"""
import threading

import rospy
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry

from rbx1_nav.common.master_ros import MasterWatch, reregister_node, topic_graph
from rbx1_nav.common.node_ros import start_node
from rbx1_nav.common.ros_time import time_moved_back_text
from rbx1_nav.estimation.input_check import RejectedInput
from rbx1_nav.estimation.odom_ekf import (SENSOR, PoseToOdometry,
                                          input_publishers, silent_input_text)

SILENT = 5.0  # wall s without input before the warning


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
        # topic_graph has a timeout: an unreachable master blocks nothing.
        publishers, candidates = input_publishers(self.input_topic,
                                                  topic_graph())
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


def main(specs, doc):
    """main() of odom_ekf.py: start the node with its parameters ``specs``
    (``doc``: its docstring, for --help) and republish until shutdown;
    returns the exit status (1: a bad parameter)."""
    values = start_node('odom_ekf', specs, doc)
    if values is None:
        return 1
    MasterWatch('odom_ekf', on_restarted=lambda uri: reregister_node(
        'odom_ekf', uri)).start()
    OdomEkfNode(values)
    rospy.spin()
    return 0
