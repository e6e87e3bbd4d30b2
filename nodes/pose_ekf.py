#!/usr/bin/env python3
"""A drop-in for robot_pose_ekf: fuse wheel odometry with a gyro's yaw.

Subscribes ``odom`` (nav_msgs/Odometry) and ``imu_data`` (sensor_msgs/Imu);
publishes ``~odom_combined`` (geometry_msgs/PoseWithCovarianceStamped) and
the tf ``output_frame -> base_footprint_frame``. The filter lives in
``rbx1_nav.pose_ekf``; this node only converts messages and keeps time.

Private parameters (robot_pose_ekf's names and defaults):
  ~output_frame (str, 'odom'), ~base_footprint_frame (str, 'base_footprint'),
  ~freq (float, 30.0): filter steps per second, 0.01 to 1000,
  ~sensor_timeout (float, 1.0): seconds without messages before a sensor is
      left out of the fusion,
  ~odom_used (bool, true), ~imu_used (bool, true),
  ~vo_used (bool, false): accepted for compatibility; visual odometry is not
      supported and is ignored.
The IMU's yaw is used as is: mount it with its z axis up. A bad parameter
is logged and the node exits with status 1. Absurd sensor messages are
dropped with a warning, and should the estimate ever stop being finite the
filter restarts instead of publishing it.
"""
import threading

import rospy
import tf2_ros
from geometry_msgs.msg import (PoseWithCovarianceStamped, Quaternion,
                               TransformStamped)
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu

from rbx1_nav.params import flag, frame, number
from rbx1_nav.pose_ekf import (GyroOdomFusion, covariance_6x6,
                               is_finite_estimate, pose_covariance_3x3)
from rbx1_nav.transform_utils import quat_to_angle, yaw_to_quaternion

WARN_PERIOD = 5.0  # s between repeats of the same warning
MIN_FREQ, MAX_FREQ = 0.01, 1000.0  # Hz, bounds of ~freq


def param(name, default, check, **options):
    """Parameter ``name`` checked by a rbx1_nav.params function."""
    return check(name, rospy.get_param(name, default), **options)


class PoseEkfNode(object):
    """Feeds sensor messages to GyroOdomFusion and publishes its estimate."""

    def __init__(self):
        self.output_frame = param('~output_frame', 'odom', frame)
        self.base_frame = param('~base_footprint_frame', 'base_footprint',
                                frame)
        self.freq = param('~freq', 30.0, number, minimum=MIN_FREQ,
                          maximum=MAX_FREQ)
        timeout = param('~sensor_timeout', 1.0, number, minimum=0.0,
                        allow_zero=False)
        odom_used = param('~odom_used', True, flag)
        imu_used = param('~imu_used', True, flag)
        vo_used = param('~vo_used', False, flag)
        rospy.loginfo('pose_ekf: output_frame=%s base_footprint_frame=%s '
                      'freq=%g sensor_timeout=%g odom_used=%s imu_used=%s '
                      'vo_used=%s', self.output_frame, self.base_frame,
                      self.freq, timeout, odom_used, imu_used, vo_used)
        if vo_used:
            rospy.logwarn('pose_ekf: vo_used is set, but visual odometry is '
                          'not supported; fusing odometry and IMU only')
        self.fusion = GyroOdomFusion(odom_used, imu_used, timeout)
        self.lock = threading.Lock()
        self.pub = rospy.Publisher('~odom_combined', PoseWithCovarianceStamped,
                                   queue_size=10)
        self.tf = tf2_ros.TransformBroadcaster()
        self.subs = []
        if odom_used:
            self.subs.append(rospy.Subscriber('odom', Odometry, self.on_odom,
                                              queue_size=50))
        if imu_used:
            self.subs.append(rospy.Subscriber('imu_data', Imu, self.on_imu,
                                              queue_size=50))

    @staticmethod
    def _stamp(header, now):
        """The message stamp, or the receive time for an unstamped message."""
        return header.stamp if not header.stamp.is_zero() else now

    def on_odom(self, msg):
        """Hand an odometry pose and its covariance to the filter."""
        now = rospy.Time.now()
        pose = msg.pose.pose
        try:
            reading = ((pose.position.x, pose.position.y,
                        quat_to_angle(pose.orientation)),
                       pose_covariance_3x3(msg.pose.covariance))
            with self.lock:
                self.fusion.add_odom(now.to_sec(), self._stamp(msg.header, now),
                                     *reading)
        except ValueError as err:
            rospy.logwarn_throttle(WARN_PERIOD, 'pose_ekf: dropped odom: %s'
                                   % err)

    def on_imu(self, msg):
        """Hand the IMU's yaw and its variance to the filter."""
        now = rospy.Time.now()
        if msg.orientation_covariance[0] == -1.0:
            rospy.logwarn_throttle(WARN_PERIOD, 'pose_ekf: dropped imu_data: it has '
                                   'no orientation (covariance[0] == -1)')
            return
        try:
            yaw = quat_to_angle(msg.orientation)
            with self.lock:
                self.fusion.add_imu(now.to_sec(), self._stamp(msg.header, now),
                                    yaw, msg.orientation_covariance[8])
        except ValueError as err:
            rospy.logwarn_throttle(WARN_PERIOD, 'pose_ekf: dropped imu_data: %s'
                                   % err)

    def step(self):
        """One filter step; publish the estimate if it took in new data.

        A non-finite estimate is never published: the filter restarts.
        """
        with self.lock:
            try:
                events = self.fusion.step(rospy.Time.now().to_sec())
                estimate = self.fusion.estimate if self.fusion.updated else None
                if not is_finite_estimate(estimate):
                    raise ValueError('the estimate is not finite')
            except (ValueError, ArithmeticError) as err:
                self.fusion.restart()
                events, estimate = [], None
                rospy.logwarn_throttle(WARN_PERIOD, 'pose_ekf: filter restarted'
                                       ' (%s); waiting for new sensor data' % err)
        for level, text in events:
            (rospy.logwarn if level == 'warn' else rospy.loginfo)(
                'pose_ekf: ' + text)
        if estimate is not None:
            self.publish(*estimate)

    def publish(self, stamp, pose, cov3):
        """Publish ``~odom_combined`` and the output -> base tf."""
        x, y, yaw = pose
        msg = PoseWithCovarianceStamped()
        msg.header.stamp = stamp
        msg.header.frame_id = self.output_frame
        msg.pose.pose.position.x, msg.pose.pose.position.y = x, y
        msg.pose.pose.orientation = Quaternion(*yaw_to_quaternion(yaw))
        msg.pose.covariance = covariance_6x6(cov3)
        tf = TransformStamped()
        tf.header = msg.header
        tf.child_frame_id = self.base_frame
        tf.transform.translation.x, tf.transform.translation.y = x, y
        tf.transform.rotation = msg.pose.pose.orientation
        self.pub.publish(msg)
        self.tf.sendTransform(tf)

    def spin(self):
        """Step at ``~freq`` (ROS time, so sim time works) until shutdown."""
        rate = rospy.Rate(self.freq)
        while not rospy.is_shutdown():
            self.step()
            try:
                rate.sleep()
            except rospy.exceptions.ROSTimeMovedBackwardsException:
                rospy.logwarn('pose_ekf: ROS time moved backwards')
            except rospy.ROSInterruptException:
                break


def main():
    rospy.init_node('robot_pose_ekf')
    try:
        node = PoseEkfNode()
    except ValueError as err:
        rospy.logfatal('pose_ekf: %s' % err)
        raise SystemExit(1)
    node.spin()


if __name__ == '__main__':
    main()
