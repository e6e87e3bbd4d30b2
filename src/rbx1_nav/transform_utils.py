"""Angle and frame helpers for planar robots: yaw <-> quaternion, angle wrapping, tf2-style
frame ids. Pure Python (no rospy, no PyKDL): the course logic and its tests need no ROS."""
import math
from collections import namedtuple

__all__ = ['Pose2D', 'quat_to_angle', 'yaw_to_quaternion', 'normalize_angle', 'strip_leading_slash']

Pose2D = namedtuple('Pose2D', 'x y yaw', defaults=(0.0, 0.0, 0.0))
Pose2D.__doc__ = 'A planar pose: position (m) and heading (rad).'


def _quat_components(q):
    """Return (x, y, z, w) of a Quaternion-like object or a 4-sequence."""
    if all(hasattr(q, name) for name in 'xyzw'):
        return q.x, q.y, q.z, q.w
    try:
        x, y, z, w = q
    except (TypeError, ValueError):
        raise ValueError('quaternion must have x, y, z, w fields or be an (x, y, z, w) '
                         'sequence, got %r' % (q,))
    return x, y, z, w


def quat_to_angle(q):
    """Yaw (rotation about z) of quaternion ``q`` in radians, in (-pi, pi]. ``q``: a
    geometry_msgs/Quaternion, anything with ``x y z w``, or an ``(x, y, z, w)`` sequence;
    normalised first. ValueError for a zero-length or non-finite one."""
    x, y, z, w = (float(c) for c in _quat_components(q))
    if not all(math.isfinite(c) for c in (x, y, z, w)):
        raise ValueError('quaternion has a non-finite component: (%r, %r, %r, %r)' % (x, y, z, w))
    norm = math.sqrt(x * x + y * y + z * z + w * w)
    if norm == 0.0:
        raise ValueError('quaternion has zero length; it encodes no rotation')
    x, y, z, w = x / norm, y / norm, z / norm, w / norm
    # ZYX Euler yaw; normalised first so huge inputs do not overflow the squares.
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return math.pi if yaw == -math.pi else yaw


def normalize_angle(angle):
    """The angle equivalent to ``angle`` (radians) in [-pi, pi], in constant time however
    large; ValueError for NaN or infinity."""
    angle = float(angle)
    if not math.isfinite(angle):
        raise ValueError('cannot normalise a non-finite angle: %r' % angle)
    # math.remainder is exact (IEEE remainder), so this also holds for 1e300.
    return math.remainder(angle, 2.0 * math.pi)


def yaw_to_quaternion(yaw):
    """(x, y, z, w) of the rotation by ``yaw`` radians about z."""
    return (0.0, 0.0, math.sin(0.5 * yaw), math.cos(0.5 * yaw))


def strip_leading_slash(frame_id):
    """``frame_id`` without leading slashes (tf2 rejects them)."""
    return str(frame_id).lstrip('/')
