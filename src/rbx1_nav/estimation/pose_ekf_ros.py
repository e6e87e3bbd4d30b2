"""The ROS side of pose_ekf.py: subscriptions, tf, the ``~get_status``
service and the filter loop, wired to
:class:`rbx1_nav.estimation.fusion.GyroOdomFusion`.

Under lockstep simulated time (rbx1_nav.sim_time.member_ros) the
filter is a member: granted each of its ticks, it takes exactly the
sensor messages the grant counts (the simulator's or bag player's, all
sent before the grant), feeds them in stamp order at the tick's time,
steps, publishes its estimate counted, and reports its next tick. So a
replay or a simulated course gives the same estimates to the last digit
however busy the machine; until its first estimate it has no tick of its
own and follows the other members' steps.

Messages become plain values and back in
:mod:`rbx1_nav.estimation.pose_ekf`; the texts come from
:mod:`rbx1_nav.estimation.status`. The node file declares the parameters
and calls :func:`main`.
"""
import math
import threading

import rospy
import tf2_ros
from geometry_msgs.msg import PoseWithCovarianceStamped
from std_srvs.srv import Trigger, TriggerResponse
from tf2_msgs.msg import TFMessage

from rbx1_nav.sim_time import member_ros as lockstep
from rbx1_nav.sim_time import switch_ros
from rbx1_nav.sim_time.member import BACK, NO_TICK
from rbx1_nav.common.master_ros import MasterWatch
from rbx1_nav.common.reregister_ros import reregister_node
from rbx1_nav.common.node_ros import forget_command_line, start_node, until_shutdown
from rbx1_nav.common.ros_time import time_moved_back_text
from rbx1_nav.common.rospy_private_ros import connection_header, connections, publisher_name
from rbx1_nav.common.tf_publishers import foreign_parent
from rbx1_nav.estimation.ekf import is_finite_estimate
from rbx1_nav.estimation.fusion import GyroOdomFusion
from rbx1_nav.estimation.input_check import RejectedInput, source_text
from rbx1_nav.estimation.pose_ekf import (TOPICS, gps_fix, imu_yaw,
                                          planar_pose, pose_message,
                                          transform_message)
from rbx1_nav.estimation.status import (OtherPublisherWatch, listening_text,
                                        other_publisher_text, output_text,
                                        silent_sensor_text)

WARN_PERIOD = 5.0  # s between repeats of the same warning
CONFLICT_PERIOD = 30.0  # s between repeats of the second-publisher error
#: Wall seconds the filter waits, under lockstep, for each of its inputs
#: to be connected to its publishers before it joins
#: (rbx1_nav.sim_time.member_ros.Member.wait_for_inputs).
INPUT_WAIT = 10.0


def connected_publishers(subscriber):
    """The nodes ``subscriber`` is connected to, or None if unknown.

    From rospy's own connections, not the master: asking a busy (or
    unreachable) master would hold up the filter loop, and with it the
    warning this feeds.
    """
    try:
        return sorted(publisher_name(c) for c in connections(subscriber))
    except AttributeError:  # rospy's internals changed
        return None


class PoseEkfNode(object):
    """Feeds sensor messages to GyroOdomFusion and publishes its estimate."""

    def __init__(self, values):
        started = rospy.Time.now()  # before the topics connect
        self.member = None
        self.output_frame = values['output_frame']
        self.base_frame = values['base_footprint_frame']
        self.freq = values['freq']
        self.publish_tf = values['publish_tf']
        used = {name: values[name + '_used'] for name in TOPICS}
        topics = {name: rospy.resolve_name(TOPICS[name][0]) for name in TOPICS}
        self.fusion = GyroOdomFusion(
            used['odom'], used['imu'], values['sensor_timeout'], used['vo'],
            used['gps'], topics, values['gps_kalman'],
            math.radians(values['gps_frame_rotation_sd'])
            if values['gps_frame_rotation'] else None, self.freq)
        self.lock = threading.Lock()
        if switch_ros.lockstep():
            self.member = lockstep.Member(
                inputs=[topics[name] for name in TOPICS if used[name]], hold=True,
                passive=True)
            self.pub = self.member.publisher(rospy.resolve_name('~odom_combined'),
                                             PoseWithCovarianceStamped)
            self.tf = (self.member.publisher(rospy.resolve_name('/tf'), TFMessage)
                       if self.publish_tf else None)
        else:
            if not started.is_zero():
                self.fusion.start(started.to_sec())
            self.pub = rospy.Publisher('~odom_combined', PoseWithCovarianceStamped,
                                       queue_size=10)
            self.tf = tf2_ros.TransformBroadcaster() if self.publish_tf else None
        self.feeds = {'odom': (self.fusion.add_odom, planar_pose),
                      'imu': (self.fusion.add_imu, imu_yaw),
                      'vo': (self.fusion.add_vo, planar_pose),
                      'gps': (self.fusion.add_gps, gps_fix)}
        self.subs, self.topics = {}, {}
        for name, (topic, msg_type) in TOPICS.items():
            if used[name]:
                # Under lockstep each tick waits for its inputs: no Nagle
                # delay (40 ms with the receiver's delayed ack); rospy's
                # publisher takes the subscriber's choice.
                sub = rospy.Subscriber(topic, msg_type, self.on_sensor, name,
                                       queue_size=None if self.member else 50,
                                       tcp_nodelay=self.member is not None)
                self.subs[name], self.topics[name] = sub, sub.resolved_name
        rospy.loginfo('pose_ekf: ' + listening_text(
            self.topics, self.pub.resolved_name, self.output_frame,
            self.base_frame, self.publish_tf))
        self.conflicts = OtherPublisherWatch(CONFLICT_PERIOD)
        self.tf_sub = None
        if self.publish_tf:
            # '/tf' as the broadcaster names it, so a <remap from="/tf">
            # applies to both.
            self.tf_sub = rospy.Subscriber('/tf', TFMessage, self.on_tf,
                                           queue_size=100)
        self.status_srv = rospy.Service('~get_status', Trigger,
                                        self.on_get_status)

    # -- inputs -----------------------------------------------------------------
    def on_sensor(self, msg, name):
        """A message of sensor ``name`` (odom, imu, vo, gps): to the filter
        at once, or under lockstep held until a grant counts it."""
        if self.member is not None:
            self.member.arrived(self.topics[name], msg, (name, msg))
        else:
            self._feed(name, msg)

    def _feed(self, name, msg, now=None):
        """Give the filter one message of sensor ``name``, received at ROS
        time ``now`` (None: read now).

        ``unpack(inputs, name, msg)`` (rbx1_nav.estimation.pose_ekf: an
        odometry or visual odometry pose, the IMU's yaw, a GPS fix) gives
        the reading's arguments to ``add`` after the receive time and the
        stamp. The ROS time is read under the lock, so the filter sees it
        in order; a drop (RejectedInput) is logged outside the lock, at
        most once per sensor and kind every 10 s.
        """
        add, unpack = self.feeds[name]
        texts = []
        with self.lock:
            now = self._clock_now(texts, now)
            try:
                add(now, msg.header.stamp.to_sec(),
                    *unpack(self.fusion.inputs, name, msg))
            except RejectedInput as err:
                texts.append(self.fusion.inputs.warning(err, now, source_text(
                    name, self.topics[name], connection_header(msg).get('callerid'))))
        for text in texts:
            if text:
                rospy.logwarn('pose_ekf: ' + text)

    def _clock_now(self, texts, now=None):
        """ROS time in seconds (``now`` if given); restarts the filter (and
        says so in ``texts``) should it have moved backwards. Call under
        the lock."""
        if now is None:
            now = rospy.Time.now().to_sec()
        back = self.fusion.check_clock(now)
        if back > 0.0:
            texts.append(time_moved_back_text(back))
        return now

    def on_tf(self, msg):
        """Spot another node publishing our child frame on tf."""
        caller = connection_header(msg).get('callerid', '?')
        parent = foreign_parent(caller, rospy.get_name(), msg.transforms,
                                self.base_frame)
        if parent and self.conflicts.seen(caller, rospy.Time.now().to_sec()):
            rospy.logerr('pose_ekf: ' + other_publisher_text(
                caller, parent, self.base_frame, self.tf_sub.resolved_name))

    def on_get_status(self, _request):
        now = rospy.Time.now().to_sec()
        with self.lock:
            text = self.fusion.status_text(now, self.topics)
        text += '\n' + output_text(
            self.pub.resolved_name, self.output_frame, self.base_frame,
            self.publish_tf, self.conflicts.publishers)
        return TriggerResponse(success=self.fusion.estimate is not None,
                               message=text)

    # -- the loop ---------------------------------------------------------------
    def step(self, now=None):
        """One filter step at ROS time ``now`` (None: read now); publish the
        estimate if it took in new data.

        A non-finite estimate is never published: the filter restarts.
        """
        if now is None and rospy.Time.now().is_zero():  # simulated time has not started
            return
        texts = []
        with self.lock:
            now = self._clock_now(texts, now)
            try:
                events = self.fusion.step(now)
                estimates = self.fusion.new_estimates
                if not all(is_finite_estimate(e) for e in estimates):
                    raise ValueError('the estimate is not finite')
            except (ValueError, ArithmeticError) as err:
                self.fusion.restart()
                events, estimates = [], []
                rospy.logwarn_throttle(WARN_PERIOD, 'pose_ekf: filter restarted'
                                       ' (%s); waiting for new sensor data' % err)
            silent = [(name, self.fusion.inputs.rejected(name))
                      for name in self.fusion.silent_sensors(now)]
            gone = self.conflicts.gone(now)
        for text in texts:
            rospy.logwarn('pose_ekf: ' + text)
        for level, text in events:
            (rospy.logwarn if level == 'warn' else rospy.loginfo)(
                'pose_ekf: ' + text)
        for name, rejected in silent:
            topic = self.topics[name]
            rospy.logwarn('pose_ekf: ' + silent_sensor_text(
                name, topic, self.fusion.sensor_timeout,
                connected_publishers(self.subs[name]), rejected))
        for caller in gone:
            rospy.loginfo('pose_ekf: %s no longer publishes %s on tf',
                          caller, self.base_frame)
        for estimate in estimates:
            self.publish(*estimate)

    def publish(self, stamp, pose, cov3):
        """Publish ``~odom_combined`` and (with ~publish_tf) the tf."""
        msg = pose_message(rospy.Time.from_sec(stamp), self.output_frame,
                           pose, cov3)
        self.pub.publish(msg)
        if self.tf is None:
            return
        transform = transform_message(msg, self.base_frame)
        if self.member is None:
            self.tf.sendTransform(transform)
        else:
            self.tf.publish(TFMessage([transform]))

    def spin(self):
        """Step at ``~freq`` (ROS time, so sim time works) until shutdown."""
        if self.member is not None:
            self.spin_lockstep()
            return
        rate = rospy.Rate(self.freq)
        while not rospy.is_shutdown():
            self.step()
            try:
                rate.sleep()
            except rospy.exceptions.ROSTimeMovedBackwardsException:
                pass  # the next step notices it, says so and restarts
            except rospy.ROSInterruptException:
                break

    def spin_lockstep(self):
        """Step at each tick granted (a grid of 1/~freq s) until shutdown."""
        member = self.member
        rospy.on_shutdown(member.leave)
        member.wait_for_inputs(INPUT_WAIT, 'pose_ekf')
        if not member.join_patiently('pose_ekf'):
            return
        period = int(round(1e9 / self.freq))
        started = False
        old_clock = None  # after a move back: the time (ns) it moved back from
        for action, tick, grant in member.grants('pose_ekf'):
            now = tick * 1e-9
            taken = member.take(grant, key=lambda item: (
                item[1].header.stamp.to_nsec(), item[0]))
            if action == BACK:
                started = False
                old_clock = member.follower.handled
            if old_clock is not None and tick <= old_clock:
                # A new clock, still behind the old one: a message stamped
                # after the tick is the old clock's, however late it comes.
                taken = [item for item in taken
                         if item[1].header.stamp.to_nsec() <= tick]
            else:
                old_clock = None
            if taken and not started:
                # Start-up counts from the first data: the time before it
                # (a bag's player not granted yet) is not the sensors' silence.
                self.fusion.start(now)
                started = True
            for name, msg in taken:
                self._feed(name, msg, now)
            self.step(now)
            member.report(tick, NO_TICK if self.fusion.estimate is None
                          else (tick // period + 1) * period)


def main(specs, doc):
    """main() of pose_ekf.py: start the node (as robot_pose_ekf) with its
    parameters ``specs`` (``doc``: its docstring, for --help) and run the
    filter until shutdown; returns the exit status (1: a bad parameter)."""
    values = start_node('robot_pose_ekf', specs, doc)
    if values is None:
        return 1
    MasterWatch('pose_ekf', on_restarted=lambda uri: reregister_node(
        'pose_ekf', uri)).start()
    try:
        node = PoseEkfNode(values)
    except ValueError as err:
        rospy.logfatal('pose_ekf: %s' % err)
        forget_command_line()
        return 1
    until_shutdown(node.spin)
    return 0
