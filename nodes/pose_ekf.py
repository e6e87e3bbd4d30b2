#!/usr/bin/env python3
"""A drop-in for robot_pose_ekf: fuse wheel odometry, a gyro, visual
odometry and GPS into one planar pose.

Subscribes ``odom`` (nav_msgs/Odometry), ``imu_data`` (sensor_msgs/Imu),
``vo`` (nav_msgs/Odometry) and ``gps`` (nav_msgs/Odometry), each only when
used; publishes ``~odom_combined`` (geometry_msgs/PoseWithCovarianceStamped)
and, unless ``~publish_tf`` is false, the tf ``output_frame ->
base_footprint_frame``. Service ``~get_status`` (std_srvs/Trigger): the
filter's state, each sensor's, and the covariance, in ``message``. The
filter lives in ``rbx1_nav.estimation``; this node converts messages, keeps
time and watches for problems:

* a used sensor with no message ``sensor_timeout`` after start-up gets one
  warning naming its (remapped) topic and who publishes it;
* another node publishing the same transform on tf gets an error naming
  it and the fix, repeated every 30 s while it lasts.

The parameters have robot_pose_ekf's names and defaults, plus ~publish_tf
(false runs pose_ekf as an estimator only), ~gps_kalman and
~gps_frame_rotation. A sensor silent
for ~sensor_timeout is left out of the fusion and taken back when it
returns. The IMU's yaw is used as is: mount it with its z axis up. A sensor
variance of 1e5 or more, -1 or inf means "not measured": that component is
not fused (said once at info level). Without GPS the output frame starts at
the first odometry pose, known exactly. With ~gps_used, as robot_pose_ekf:
the filter starts at a GPS fix with the IMU's heading (the output frame is
the GPS frame, the IMU's yaw its heading), steps at the oldest of its
sensors' newest stamps (read off the stamps ~freq times a second, so the
answer does not depend on when messages arrive), takes the IMU's yaw as
absolute while GPS is active and the fixes on x, y only. With
~gps_frame_rotation the IMU's heading is only the prior of the heading in
the GPS frame: the rotation between the two is estimated from the fixes
as the robot moves. A bad
parameter is logged and the node exits with status 1. Unstamped,
out-of-order, repeated, NaN or absurd sensor messages and negative
variances are dropped (rbx1_nav.estimation.input_check), with one warning per sensor
and kind every 10 s that counts them, so the output's stamps only move
forward. Should the estimate ever stop being finite the filter restarts
instead of publishing it; should ROS time move backwards (a bag looping,
a simulator restarted) it says so and restarts from the next readings.
Should the ROS master restart, the node says so within a few seconds and
registers its topics, tf and service with the new master, so RViz and new
nodes find them again (rbx1_nav.common.master_ros); its connections go on.
"""
import math
import threading

import rospy
import tf2_ros
from geometry_msgs.msg import (PoseWithCovarianceStamped, Quaternion,
                               TransformStamped)
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu
from std_srvs.srv import Trigger, TriggerResponse
from tf2_msgs.msg import TFMessage

from rbx1_nav.common import params
from rbx1_nav.estimation.input_check import BAD_ORIENTATION, RejectedInput
from rbx1_nav.common.ros_time import time_moved_back_text
from rbx1_nav.estimation.ekf import covariance_6x6, is_finite_estimate, pose_covariance_3x3, position_covariance_2x2
from rbx1_nav.estimation.fusion import GyroOdomFusion
from rbx1_nav.estimation.status import OtherPublisherWatch, other_publisher_text, silent_sensor_text
from rbx1_nav.common.master_ros import MasterWatch, reregister_node
from rbx1_nav.common.node_ros import start_node, until_shutdown
from rbx1_nav.transform_utils import quat_to_angle, yaw_to_quaternion

WARN_PERIOD = 5.0  # s between repeats of the same warning
CONFLICT_PERIOD = 30.0  # s between repeats of the second-publisher error
MIN_FREQ, MAX_FREQ = 0.01, 1000.0  # Hz, bounds of ~freq

PARAMS = (
    params.param('output_frame', 'odom', params.frame, '',
                 'parent frame of the fused pose and its tf'),
    params.param('base_footprint_frame', 'base_footprint', params.frame, '',
                 'child frame of the tf'),
    params.param('freq', 30.0, params.number, 'Hz', 'filter steps per second',
                 minimum=MIN_FREQ, maximum=MAX_FREQ),
    params.param('sensor_timeout', 1.0, params.number, 's',
                 'silence before a sensor is left out', minimum=0.0,
                 allow_zero=False),
    params.param('odom_used', True, params.flag, '', 'fuse odom'),
    params.param('imu_used', True, params.flag, '', 'fuse imu_data (yaw)'),
    params.param('vo_used', False, params.flag, '', 'fuse vo (relative pose)'),
    params.param('gps_used', False, params.flag, '',
                 'fuse gps (x, y) as robot_pose_ekf: start at the fix and '
                 'the IMU heading, output in the GPS frame'),
    params.param('gps_kalman', False, params.flag, '',
                 'with gps_used: fuse each fix once with its covariance '
                 '(Kalman gain) instead of robot_pose_ekf\'s per-step weight'),
    params.param('gps_frame_rotation', False, params.flag, '',
                 'with gps_used: estimate the rotation between the GPS frame '
                 'and the IMU\'s heading instead of taking the IMU\'s heading '
                 'as true in it (fixes fused as with gps_kalman)'),
    params.param('gps_frame_rotation_sd', 30.0, params.number, 'deg',
                 'with gps_frame_rotation: the prior standard deviation of '
                 'that rotation', minimum=0.0, maximum=180.0,
                 allow_zero=False),
    params.param('publish_tf', True, params.flag, '',
                 'publish tf output_frame -> base_footprint_frame'),
)
#: Each sensor's topic and message type (relative names, as robot_pose_ekf).
TOPICS = {'odom': ('odom', Odometry), 'imu': ('imu_data', Imu),
          'vo': ('vo', Odometry), 'gps': ('gps', Odometry)}


def connected_publishers(subscriber):
    """The nodes ``subscriber`` is connected to, or None if unknown.

    From rospy's own connections, not the master: asking a busy (or
    unreachable) master would hold up the filter loop, and with it the
    warning this feeds.
    """
    try:
        return sorted(c.callerid_pub for c in subscriber.impl.connections)
    except AttributeError:  # rospy's internals changed
        return None


class PoseEkfNode(object):
    """Feeds sensor messages to GyroOdomFusion and publishes its estimate."""

    def __init__(self, values):
        started = rospy.Time.now()  # before the topics connect
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
        if not started.is_zero():
            self.fusion.start(started.to_sec())
        self.lock = threading.Lock()
        self.pub = rospy.Publisher('~odom_combined', PoseWithCovarianceStamped,
                                   queue_size=10)
        self.tf = tf2_ros.TransformBroadcaster() if self.publish_tf else None
        callbacks = {'odom': self.on_odom, 'imu': self.on_imu,
                     'vo': self.on_vo, 'gps': self.on_gps}
        self.subs, self.topics = {}, {}
        for name, (topic, msg_type) in TOPICS.items():
            if used[name]:
                sub = rospy.Subscriber(topic, msg_type, callbacks[name],
                                       queue_size=50)
                self.subs[name], self.topics[name] = sub, sub.resolved_name
        rospy.loginfo('pose_ekf: listening on %s; publishing %s%s', ', '.join(
            '%s %s' % item for item in sorted(self.topics.items())),
            self.pub.resolved_name,
            ' and tf %s -> %s' % (self.output_frame, self.base_frame)
            if self.publish_tf else ' only (~publish_tf false: no tf)')
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
    def _feed(self, name, add, unpack, msg):
        """Give the filter one message of sensor ``name``.

        ``unpack(name, msg)`` gives the reading's arguments to ``add``
        after the receive time and the stamp. The ROS time is read under
        the lock, so the filter sees it in order; a drop (RejectedInput)
        is logged outside the lock, at most once per sensor and kind every
        10 s.
        """
        texts = []
        with self.lock:
            now = self._clock_now(texts)
            try:
                add(now, msg.header.stamp.to_sec(), *unpack(name, msg))
            except RejectedInput as err:
                texts.append(self.fusion.inputs.warning(
                    err, now, '%s on %s' % (name, self.topics[name])))
        for text in texts:
            if text:
                rospy.logwarn('pose_ekf: ' + text)

    def _clock_now(self, texts):
        """ROS time in seconds; restarts the filter (and says so in
        ``texts``) should it have moved backwards. Call under the lock."""
        now = rospy.Time.now().to_sec()
        back = self.fusion.check_clock(now)
        if back > 0.0:
            texts.append(time_moved_back_text(back))
        return now

    def _yaw(self, name, orientation):
        try:
            return quat_to_angle(orientation)
        except ValueError as err:
            raise self.fusion.inputs.reject(name, BAD_ORIENTATION, str(err))

    def _planar_pose(self, name, msg):
        pose = msg.pose.pose
        return ((pose.position.x, pose.position.y,
                 self._yaw(name, pose.orientation)),
                pose_covariance_3x3(msg.pose.covariance))

    def _imu_yaw(self, name, msg):
        if msg.orientation_covariance[0] == -1.0:
            raise self.fusion.inputs.reject(
                name, BAD_ORIENTATION, 'orientation_covariance[0] is -1: the '
                'IMU gives no orientation')
        return self._yaw(name, msg.orientation), msg.orientation_covariance[8]

    @staticmethod
    def _gps_fix(_name, msg):
        position = msg.pose.pose.position
        return ((position.x, position.y),
                position_covariance_2x2(msg.pose.covariance))

    def on_odom(self, msg):
        """Hand an odometry pose and its covariance to the filter."""
        self._feed('odom', self.fusion.add_odom, self._planar_pose, msg)

    def on_vo(self, msg):
        """Hand a visual odometry pose and its covariance to the filter."""
        self._feed('vo', self.fusion.add_vo, self._planar_pose, msg)

    def on_gps(self, msg):
        """Hand a GPS fix (x, y; z ignored) and its covariance to the filter."""
        self._feed('gps', self.fusion.add_gps, self._gps_fix, msg)

    def on_imu(self, msg):
        """Hand the IMU's yaw and its variance to the filter."""
        self._feed('imu', self.fusion.add_imu, self._imu_yaw, msg)

    def on_tf(self, msg):
        """Spot another node publishing our child frame on tf."""
        caller = msg._connection_header.get('callerid', '?')
        if caller == rospy.get_name():
            return
        for tf in msg.transforms:
            if tf.child_frame_id.lstrip('/') != self.base_frame:
                continue
            if self.conflicts.seen(caller, rospy.Time.now().to_sec()):
                rospy.logerr('pose_ekf: ' + other_publisher_text(
                    caller, tf.header.frame_id.lstrip('/'), self.base_frame,
                    self.tf_sub.resolved_name))
            return

    def on_get_status(self, _request):
        now = rospy.Time.now().to_sec()
        with self.lock:
            text = self.fusion.status_text(now, self.topics)
        text += '\noutput: %s, tf %s' % (
            self.pub.resolved_name, '%s -> %s' % (
                self.output_frame, self.base_frame) if self.publish_tf
            else 'off (~publish_tf false)')
        others = self.conflicts.publishers
        if others:
            text += '\nalso publishing %s on tf: %s' % (self.base_frame,
                                                        ', '.join(others))
        return TriggerResponse(success=self.fusion.estimate is not None,
                               message=text)

    # -- the loop ---------------------------------------------------------------
    def step(self):
        """One filter step; publish the estimate if it took in new data.

        A non-finite estimate is never published: the filter restarts.
        """
        if rospy.Time.now().is_zero():  # simulated time has not started
            return
        texts = []
        with self.lock:
            now = self._clock_now(texts)
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
            silent = self.fusion.silent_sensors(now)
            gone = self.conflicts.gone(now)
        for text in texts:
            rospy.logwarn('pose_ekf: ' + text)
        for level, text in events:
            (rospy.logwarn if level == 'warn' else rospy.loginfo)(
                'pose_ekf: ' + text)
        for name in silent:
            topic = self.topics[name]
            rospy.logwarn('pose_ekf: ' + silent_sensor_text(
                name, topic, self.fusion.sensor_timeout,
                connected_publishers(self.subs[name])))
        for caller in gone:
            rospy.loginfo('pose_ekf: %s no longer publishes %s on tf',
                          caller, self.base_frame)
        for estimate in estimates:
            self.publish(*estimate)

    def publish(self, stamp, pose, cov3):
        """Publish ``~odom_combined`` and (with ~publish_tf) the tf."""
        x, y, yaw = pose
        msg = PoseWithCovarianceStamped()
        msg.header.stamp = rospy.Time.from_sec(stamp)
        msg.header.frame_id = self.output_frame
        msg.pose.pose.position.x, msg.pose.pose.position.y = x, y
        msg.pose.pose.orientation = Quaternion(*yaw_to_quaternion(yaw))
        msg.pose.covariance = covariance_6x6(cov3)
        self.pub.publish(msg)
        if self.tf is not None:
            tf = TransformStamped()
            tf.header = msg.header
            tf.child_frame_id = self.base_frame
            tf.transform.translation.x, tf.transform.translation.y = x, y
            tf.transform.rotation = msg.pose.pose.orientation
            self.tf.sendTransform(tf)

    def spin(self):
        """Step at ``~freq`` (ROS time, so sim time works) until shutdown."""
        rate = rospy.Rate(self.freq)
        while not rospy.is_shutdown():
            self.step()
            try:
                rate.sleep()
            except rospy.exceptions.ROSTimeMovedBackwardsException:
                pass  # the next step notices it, says so and restarts
            except rospy.ROSInterruptException:
                break


def main():
    values = start_node('robot_pose_ekf', PARAMS, __doc__)
    if values is None:
        raise SystemExit(1)
    MasterWatch('pose_ekf', on_restarted=lambda uri: reregister_node(
        'pose_ekf', uri)).start()
    try:
        node = PoseEkfNode(values)
    except ValueError as err:
        rospy.logfatal('pose_ekf: %s' % err)
        raise SystemExit(1)
    until_shutdown(node.spin)


if __name__ == '__main__':
    main()
