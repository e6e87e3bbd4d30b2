"""pose_ekf's messages as plain values, and its estimate as messages.

Each sensor message becomes the arguments that
:class:`rbx1_nav.estimation.fusion.GyroOdomFusion` takes after the receive
time and the stamp (:func:`planar_pose`, :func:`imu_yaw`, :func:`gps_fix`);
an estimate ``(stamp, (x, y, yaw), cov3)`` becomes the
PoseWithCovarianceStamped and the transform the node publishes
(:func:`pose_message`, :func:`transform_message`). The ROS side is
:mod:`rbx1_nav.estimation.pose_ekf_ros`. This module imports no rospy:
message classes load without a master.
"""
from geometry_msgs.msg import (PoseWithCovarianceStamped, Quaternion,
                               TransformStamped)
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu

from rbx1_nav.estimation.ekf import (covariance_6x6, pose_covariance_3x3,
                                     position_covariance_2x2)
from rbx1_nav.estimation.input_check import BAD_ORIENTATION
from rbx1_nav.transform_utils import quat_to_angle, yaw_to_quaternion

__all__ = ['TOPICS', 'planar_pose', 'imu_yaw', 'gps_fix', 'pose_message',
           'transform_message']

#: Each sensor's topic and message type (relative names, as robot_pose_ekf).
TOPICS = {'odom': ('odom', Odometry), 'imu': ('imu_data', Imu),
          'vo': ('vo', Odometry), 'gps': ('gps', Odometry)}


def _yaw(inputs, name, orientation):
    try:
        return quat_to_angle(orientation)
    except ValueError as err:
        raise inputs.reject(name, BAD_ORIENTATION, str(err))


def planar_pose(inputs, name, msg):
    """``((x, y, yaw), cov3)`` of an Odometry ``msg`` of sensor ``name``
    (odom, vo).

    A quaternion without a yaw is counted in ``inputs``
    (rbx1_nav.estimation.input_check.InputCheck) and raised as
    RejectedInput.
    """
    pose = msg.pose.pose
    return ((pose.position.x, pose.position.y,
             _yaw(inputs, name, pose.orientation)),
            pose_covariance_3x3(msg.pose.covariance))


def imu_yaw(inputs, name, msg):
    """``(yaw, variance)`` of an Imu ``msg``; an IMU that gives no
    orientation (``orientation_covariance[0]`` -1) or a quaternion without
    a yaw is counted in ``inputs`` and raised as RejectedInput."""
    if msg.orientation_covariance[0] == -1.0:
        raise inputs.reject(
            name, BAD_ORIENTATION, 'orientation_covariance[0] is -1: the '
            'IMU gives no orientation')
    return _yaw(inputs, name, msg.orientation), msg.orientation_covariance[8]


def gps_fix(_inputs, _name, msg):
    """``((x, y), cov2)`` of a GPS fix (an Odometry ``msg``; z ignored)."""
    position = msg.pose.pose.position
    return ((position.x, position.y),
            position_covariance_2x2(msg.pose.covariance))


def pose_message(stamp, frame_id, pose, cov3):
    """The PoseWithCovarianceStamped of ``pose`` ``(x, y, yaw)`` with the
    3x3 covariance ``cov3``, stamped ``stamp`` (a Time) in ``frame_id``."""
    x, y, yaw = pose
    msg = PoseWithCovarianceStamped()
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    msg.pose.pose.position.x, msg.pose.pose.position.y = x, y
    msg.pose.pose.orientation = Quaternion(*yaw_to_quaternion(yaw))
    msg.pose.covariance = covariance_6x6(cov3)
    return msg


def transform_message(pose_msg, child_frame_id):
    """The transform ``pose_msg``'s frame -> ``child_frame_id`` that
    ``pose_msg`` (a :func:`pose_message`) describes; it shares the header."""
    tf = TransformStamped()
    tf.header = pose_msg.header
    tf.child_frame_id = child_frame_id
    position = pose_msg.pose.pose.position
    tf.transform.translation.x, tf.transform.translation.y = (position.x,
                                                              position.y)
    tf.transform.rotation = pose_msg.pose.pose.orientation
    return tf
