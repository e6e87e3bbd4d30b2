"""Turn fused PoseWithCovarianceStamped messages into nav_msgs/Odometry.

robot_pose_ekf (and ``pose_ekf.py`` here) publish their estimate as a
geometry_msgs/PoseWithCovarianceStamped on ``odom_combined``. RViz's Odometry
display wants nav_msgs/Odometry, so ``nodes/odom_ekf.py`` republishes each
pose through :class:`PoseToOdometry`. This module imports no rospy: message
classes from geometry_msgs and nav_msgs load without a master.
"""
import copy
import math

from nav_msgs.msg import Odometry

from rbx1_nav.diff_drive import covariance_from_diagonal
from rbx1_nav.transform_utils import (normalize_angle, quat_to_angle,
                                      strip_leading_slash)

__all__ = ['PoseToOdometry', 'UNKNOWN_VARIANCE']

#: Variance that marks a twist component as unknown (the common ROS idiom).
UNKNOWN_VARIANCE = 1e6


def _check_finite(msg):
    """Raise ValueError unless the pose and covariance of ``msg`` are finite."""
    pose = msg.pose.pose
    numbers = (pose.position.x, pose.position.y, pose.position.z,
               pose.orientation.x, pose.orientation.y, pose.orientation.z,
               pose.orientation.w)
    if not all(math.isfinite(v) for v in numbers):
        raise ValueError('pose has a NaN or infinite component')
    if len(msg.pose.covariance) != 36:
        raise ValueError('covariance has %d entries, expected 36'
                         % len(msg.pose.covariance))
    if not all(math.isfinite(v) for v in msg.pose.covariance):
        raise ValueError('covariance has a NaN or infinite entry')
    if all(v == 0.0 for v in numbers[3:]):
        raise ValueError('orientation is an all-zero quaternion')


class PoseToOdometry(object):
    """Map PoseWithCovarianceStamped messages to nav_msgs/Odometry.

    ``frame_id`` (if non-empty) overrides the input's frame; an input without
    a frame gets ``default_frame_id``. ``child_frame_id`` names the robot's
    base frame. With ``estimate_twist`` the twist is the body-frame velocity
    between the previous and the current pose (``twist_variance`` on the
    planar components, :data:`UNKNOWN_VARIANCE` on the rest); otherwise, and
    for the first pose, the twist is zero and marked unknown.
    """

    def __init__(self, frame_id='', child_frame_id='base_footprint',
                 estimate_twist=True, twist_variance=0.01,
                 default_frame_id='odom'):
        self.frame_id = strip_leading_slash(frame_id)
        self.child_frame_id = strip_leading_slash(child_frame_id)
        self.default_frame_id = strip_leading_slash(default_frame_id)
        self.estimate_twist = bool(estimate_twist)
        self.twist_variance = float(twist_variance)
        if not (math.isfinite(self.twist_variance)
                and self.twist_variance > 0.0):
            raise ValueError('twist_variance must be a positive number, got %r'
                             % (twist_variance,))
        self._previous = None  # (frame, time [s], x, y, yaw)

    def convert(self, msg):
        """Odometry for ``msg``; raises ValueError for a NaN or broken pose.

        ``msg`` is never modified: the pose is deep-copied.
        """
        _check_finite(msg)
        odom = Odometry()
        odom.header.seq = msg.header.seq
        odom.header.stamp = copy.deepcopy(msg.header.stamp)
        odom.header.frame_id = (self.frame_id
                                or strip_leading_slash(msg.header.frame_id)
                                or self.default_frame_id)
        odom.child_frame_id = self.child_frame_id
        odom.pose.pose = copy.deepcopy(msg.pose.pose)
        odom.pose.covariance = [float(v) for v in msg.pose.covariance]
        self._fill_twist(odom)
        return odom

    def reset(self):
        """Forget the previous pose (e.g. after time jumped backwards)."""
        self._previous = None

    def _fill_twist(self, odom):
        """Set ``odom.twist`` from the change since the previous pose."""
        pose = odom.pose.pose
        now = (odom.header.frame_id, odom.header.stamp.to_sec(),
               pose.position.x, pose.position.y,
               quat_to_angle(pose.orientation))
        previous, self._previous = self._previous, now
        unknown = covariance_from_diagonal([UNKNOWN_VARIANCE] * 6)
        odom.twist.covariance = unknown
        if not self.estimate_twist or previous is None:
            return
        if previous[0] != now[0]:
            return  # a different frame: the two poses are not comparable
        dt = now[1] - previous[1]
        if dt <= 0.0:
            return  # repeated or backwards stamp (e.g. a restarted sim clock)
        dyaw = normalize_angle(now[4] - previous[4])
        mid_yaw = previous[4] + 0.5 * dyaw
        dx, dy = now[2] - previous[2], now[3] - previous[3]
        cos_y, sin_y = math.cos(mid_yaw), math.sin(mid_yaw)
        twist = odom.twist.twist
        twist.linear.x = (cos_y * dx + sin_y * dy) / dt
        twist.linear.y = (-sin_y * dx + cos_y * dy) / dt
        twist.angular.z = dyaw / dt
        var = self.twist_variance
        odom.twist.covariance = covariance_from_diagonal(
            [var, var, UNKNOWN_VARIANCE, UNKNOWN_VARIANCE, UNKNOWN_VARIANCE,
             var])
