"""The ROS side of odom_ekf.py: the input (``input`` when remapped, else
both ``odom_combined`` and ``robot_pose_ekf/odom_combined``, one followed
as :class:`rbx1_nav.estimation.odom_ekf.InputChoice` decides) ->
:class:`rbx1_nav.estimation.odom_ekf.PoseToOdometry` -> ``output``, the
warning when the input stays silent, and re-registration after a master
restart.

The node file declares the parameters and calls :func:`main`.
"""
import threading
import time

import rospy
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry

from rbx1_nav.common.master_ros import MasterWatch, topic_graph
from rbx1_nav.common.rospy_private_ros import connection_header
from rbx1_nav.common.reregister_ros import reregister_node
from rbx1_nav.common.node_ros import start_node
from rbx1_nav.common.ros_time import time_moved_back_text
from rbx1_nav.estimation.input_check import RejectedInput, source_text
from rbx1_nav.estimation.odom_ekf import (DEFAULT_INPUTS, SENSOR, InputChoice,
                                          PoseToOdometry, input_publishers,
                                          silent_input_text)

SILENT = 5.0  # wall s without input before the warning


def input_topics():
    """The resolved input topics: ``input`` if it is remapped, else
    :data:`DEFAULT_INPUTS` in the node's namespace."""
    remapped = rospy.resolve_name('input')
    if remapped != rospy.names.ns_join(rospy.get_namespace(), 'input'):
        return [remapped]
    return [rospy.resolve_name(name) for name in DEFAULT_INPUTS]


class OdomEkfNode(object):
    """Wires the input -> PoseToOdometry -> ``output``."""

    def __init__(self, values):
        self.converter = PoseToOdometry(**values)
        self.topics = input_topics()
        self.choice = InputChoice(self.topics)
        self.lock = threading.Lock()
        rospy.loginfo('odom_ekf: %s -> %s', ' or '.join(self.topics),
                      rospy.resolve_name('output'))
        self.pub = rospy.Publisher('output', Odometry, queue_size=10)
        self.received = threading.Event()
        # Subscribe last so no callback runs before the publisher exists.
        self.subs = [rospy.Subscriber(topic, PoseWithCovarianceStamped,
                                      self.on_pose, callback_args=topic,
                                      queue_size=10)
                     for topic in self.topics]
        threading.Thread(target=self.check_input, daemon=True,
                         name='input_check').start()

    def check_input(self):
        """Warn once if nothing came on the input within SILENT s, naming
        who publishes it and the topics it could be remapped to."""
        if self.received.wait(SILENT) or rospy.is_shutdown():
            return
        # topic_graph has a timeout: an unreachable master blocks nothing.
        publishers, candidates = input_publishers(self.topics, topic_graph())
        rospy.logwarn('odom_ekf: ' + silent_input_text(
            self.topics, SILENT, publishers, candidates))

    def on_pose(self, msg, topic):
        """Convert one fused pose of the followed input and publish it;
        drop bad input, and the other input's, with a warning."""
        self.received.set()
        # One subscriber thread each: one pose at a time through the
        # choice and the converter.
        with self.lock:
            self._on_pose(msg, topic)

    def _on_pose(self, msg, topic):
        now = rospy.Time.now().to_sec()
        # Wall time, as SILENT: a paused or fast clock changes nothing.
        choice = self.choice.offer(topic, time.monotonic())
        if choice.text:
            (rospy.logwarn if choice.level == 'warn' else rospy.loginfo)(
                'odom_ekf: ' + choice.text)
        if not choice.take:
            return
        if choice.switched:
            self.converter.new_input()
        back = self.converter.check_clock(now)
        if back > 0.0:
            rospy.logwarn('odom_ekf: ' + time_moved_back_text(back))
        try:
            odom = self.converter.convert(msg)
        except RejectedInput as err:
            text = self.converter.inputs.warning(err, now, source_text(
                SENSOR, topic, connection_header(msg).get('callerid')))
            if text:
                rospy.logwarn('odom_ekf: ' + text)
            return
        try:
            self.pub.publish(odom)
        except rospy.ROSException:
            if not rospy.is_shutdown():
                raise  # else Ctrl-C closed the topic under this callback


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
