"""Turn fused PoseWithCovarianceStamped messages into nav_msgs/Odometry.

robot_pose_ekf (and ``pose_ekf.py`` here) publish their estimate as a
geometry_msgs/PoseWithCovarianceStamped on ``odom_combined``. RViz's Odometry
display wants nav_msgs/Odometry, so ``odom_ekf.py``
(:mod:`rbx1_nav.estimation.odom_ekf_ros`) republishes each pose through
:class:`PoseToOdometry`, which drops bad input through
:class:`rbx1_nav.estimation.input_check.InputCheck` (unstamped, out-of-order or
repeated poses, NaN or absurd values, negative variances), so the output's
stamps only move forward.

Without a remap of its input the node hears two topics: the book's
``odom_combined`` (where a TurtleBot's bringup remaps robot_pose_ekf's
output) and robot_pose_ekf's own ``robot_pose_ekf/odom_combined``.
:class:`InputChoice` decides which one it follows: the first that delivers
a pose; should the other deliver too, it is ignored with one warning, and
taken over only once the followed one has been silent for
:data:`SWITCH_AFTER` s. This module imports no rospy: message classes from
geometry_msgs and nav_msgs load without a master.
"""
import copy
import math

import numpy as np
from nav_msgs.msg import Odometry

from rbx1_nav.estimation.input_check import BAD_ORIENTATION, MALFORMED, InputCheck
from rbx1_nav.common.ros_time import ClockWatch
from rbx1_nav.transform_utils import (normalize_angle, quat_to_angle,
                                      strip_leading_slash)

__all__ = ['PoseToOdometry', 'UNKNOWN_VARIANCE', 'UNKNOWN_TWIST_COVARIANCE',
           'MIN_TWIST_DT', 'MAX_TWIST', 'SENSOR', 'POSE_TYPE',
           'input_publishers', 'silent_input_text', 'InputChoice', 'Choice',
           'BOOK_INPUT', 'FILTER_INPUT', 'DEFAULT_INPUTS', 'SWITCH_AFTER']

#: Variance that marks a twist component as unknown (the common ROS idiom).
UNKNOWN_VARIANCE = 1e6
#: Row-major 6x6 twist covariance of a twist that is not known at all.
UNKNOWN_TWIST_COVARIANCE = tuple(
    np.diag([UNKNOWN_VARIANCE] * 6).ravel().tolist())
#: Poses closer in time than this (s) give no twist: dividing by a tiny dt
#: turns stamp jitter into absurd speeds.
MIN_TWIST_DT = 1e-3
#: A twist component above this (m/s or rad/s) is no robot's motion but a
#: jump of the input (a reset filter, a restarted driver): marked unknown.
MAX_TWIST = 1e3

#: The name of the input in :attr:`PoseToOdometry.inputs`.
SENSOR = 'pose'
#: The input's message type, as the master names it.
POSE_TYPE = 'geometry_msgs/PoseWithCovarianceStamped'

#: The book's name of the fused pose (its TurtleBot bringup remaps
#: robot_pose_ekf's output here), relative to the node's namespace.
BOOK_INPUT = 'odom_combined'
#: robot_pose_ekf's (and pose_ekf.py's) own name for it.
FILTER_INPUT = 'robot_pose_ekf/odom_combined'
#: The topics heard when the input is not remapped.
DEFAULT_INPUTS = (BOOK_INPUT, FILTER_INPUT)
#: Seconds the followed input must be silent, while another delivers,
#: before the node follows the other.
SWITCH_AFTER = 5.0


class PoseToOdometry(object):
    """Map PoseWithCovarianceStamped messages to nav_msgs/Odometry.

    ``frame_id`` (if non-empty) overrides the input's frame; an input without
    a frame gets ``default_frame_id``. ``child_frame_id`` names the robot's
    base frame. With ``estimate_twist`` the twist is the body-frame velocity
    between the previous and the current pose (``twist_variance`` on the
    planar components, :data:`UNKNOWN_VARIANCE` on the rest); otherwise, and
    for the first pose, poses less than :data:`MIN_TWIST_DT` apart or a
    twist that is not finite or beyond :data:`MAX_TWIST`, the twist is zero
    and marked unknown.

    :meth:`convert` drops bad input (:attr:`inputs`, sensor
    :data:`SENSOR`); call :meth:`check_clock` with the ROS time before each
    message, so that after ROS time moved backwards the poses of the new
    clock are taken.
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
        self.inputs = InputCheck()
        self._clock = ClockWatch()

    def check_clock(self, now):
        """Seconds ROS time moved back since the previous call, or 0.0.

        On a move back (a bag looping, a simulator restarted) the next pose
        is taken whatever its stamp, and gives no twist.
        """
        back = self._clock.moved_back(now)
        if back > 0.0:
            self.inputs.new_clock()
            self._previous = None
        return back

    def new_input(self):
        """The poses come from another filter from now on: forget the
        previous pose (no twist across the switch) and the newest stamp."""
        self.inputs.new_clock()
        self._previous = None

    def convert(self, msg):
        """Odometry for ``msg``, or RejectedInput (a ValueError) for an
        unstamped pose, one no newer than the last taken, a NaN or absurd
        position, a NaN covariance or a negative variance, or a zero or
        NaN orientation.

        ``msg`` is never modified: the pose is deep-copied.
        """
        self._check(msg)
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

    def _check(self, msg):
        pose, cov = msg.pose.pose, msg.pose.covariance
        if len(cov) != 36:
            raise self.inputs.reject(SENSOR, MALFORMED, 'covariance has %d '
                                     'entries, expected 36' % len(cov))
        try:
            quat_to_angle(pose.orientation)
        except ValueError as err:
            raise self.inputs.reject(SENSOR, BAD_ORIENTATION, str(err))
        position = pose.position
        self.inputs.check(SENSOR, msg.header.stamp.to_sec(),
                          position=(position.x, position.y, position.z),
                          covariance=np.reshape(cov, (6, 6)))

    def _fill_twist(self, odom):
        """Set ``odom.twist`` from the change since the previous pose."""
        pose = odom.pose.pose
        now = (odom.header.frame_id, odom.header.stamp.to_sec(),
               pose.position.x, pose.position.y,
               quat_to_angle(pose.orientation))
        previous, self._previous = self._previous, now
        odom.twist.covariance = list(UNKNOWN_TWIST_COVARIANCE)
        if not self.estimate_twist or previous is None:
            return
        if previous[0] != now[0]:
            return  # a different frame: the two poses are not comparable
        dt = now[1] - previous[1]
        if dt < MIN_TWIST_DT:
            return  # stamp jitter
        dyaw = normalize_angle(now[4] - previous[4])
        mid_yaw = previous[4] + 0.5 * dyaw
        dx, dy = now[2] - previous[2], now[3] - previous[3]
        cos_y, sin_y = math.cos(mid_yaw), math.sin(mid_yaw)
        velocity = ((cos_y * dx + sin_y * dy) / dt,
                    (-sin_y * dx + cos_y * dy) / dt, dyaw / dt)
        if not all(abs(v) <= MAX_TWIST for v in velocity):  # False for NaN
            return  # a jump, or poses too far apart for a float
        twist = odom.twist.twist
        twist.linear.x, twist.linear.y, twist.angular.z = velocity
        var = self.twist_variance
        odom.twist.covariance = np.diag(
            [var, var, UNKNOWN_VARIANCE, UNKNOWN_VARIANCE, UNKNOWN_VARIANCE,
             var]).ravel().tolist()


class Choice(object):
    """What :meth:`InputChoice.offer` decided about one pose: ``take`` it
    or not, and ``text`` to log (None: nothing) at ``level`` ('info' or
    'warn'); ``switched`` when the followed input changed (the poses
    before it came from another filter)."""

    __slots__ = ('take', 'switched', 'text', 'level')

    def __init__(self, take, switched=False, text=None, level='info'):
        self.take, self.switched = take, switched
        self.text, self.level = text, level

    def __repr__(self):
        return 'Choice(%r, %r, %r, %r)' % (self.take, self.switched,
                                           self.text, self.level)


class InputChoice(object):
    """Which of the input ``topics`` (resolved names) the node follows.

    The first topic that delivers a pose is followed. A pose from another
    topic is dropped; the first such pose of each topic gives one warning
    naming both topics (two filters, or one remapped and one not). Should
    the followed topic stay silent for ``switch_after`` s (the caller's
    clock, ``now``) while another delivers, the other is followed from
    then on, with a warning.
    """

    def __init__(self, topics, switch_after=SWITCH_AFTER):
        self.topics = tuple(topics)
        if not self.topics:
            raise ValueError('no input topics')
        self.switch_after = float(switch_after)
        self.followed = None
        self._last = {}
        self._warned = set()

    def offer(self, topic, now):
        """A :class:`Choice` for a pose that arrived on ``topic`` at
        ``now`` (seconds)."""
        if topic not in self.topics:
            raise ValueError('%s is not an input (%s)'
                             % (topic, ', '.join(self.topics)))
        self._last[topic] = now
        if self.followed is None:
            self.followed = topic
            text = 'following %s' % topic
            if len(self.topics) > 1:
                text += ' (the first of %s to publish)' % ' and '.join(
                    self.topics)
            return Choice(True, text=text)
        if topic == self.followed:
            return Choice(True)
        silent = now - self._last[self.followed]
        if silent >= self.switch_after:
            old, self.followed = self.followed, topic
            return Choice(True, switched=True, level='warn', text=(
                'nothing on %s for %.0f s while %s publishes: following %s '
                'now' % (old, silent, topic, topic)))
        if topic in self._warned:
            return Choice(False)
        self._warned.add(topic)
        return Choice(False, level='warn', text=(
            'both %s and %s carry a fused pose: following %s (it published '
            'first), ignoring %s. Two filters run, or one filter\'s output '
            'is remapped and another\'s is not. To follow the other: '
            'roslaunch rbx1_nav odom_ekf.launch input:=%s'
            % (self.followed, topic, self.followed, topic, topic)))


def _topics(topic):
    return (topic,) if isinstance(topic, str) else tuple(topic)


def input_publishers(topic, graph):
    """``(publishers, candidates)`` for :func:`silent_input_text`: the
    nodes that publish ``topic`` (a name, or a sequence of names) and the
    published topics of :data:`POSE_TYPE`, from ``graph`` (the master's
    ``(publishers, subscribers, types)``, dicts by topic name); both None
    without a ``graph``."""
    if graph is None:
        return None, None
    published, _, types = graph
    return (sorted({node for name in _topics(topic)
                    for node in published.get(name, [])}),
            [name for name, kind in types.items()
             if kind == POSE_TYPE and published.get(name)])


def silent_input_text(topic, seconds, publishers, candidates):
    """The warning when nothing came on the input ``topic`` (a name, or a
    sequence of names: the inputs heard) in ``seconds``.

    ``publishers`` are the nodes that publish ``topic`` and ``candidates``
    the published topics that carry geometry_msgs/PoseWithCovarianceStamped,
    both from the master (None when it could not tell).
    """
    topics = _topics(topic)
    text = 'nothing on %s after %.0f s; ' % (' or '.join(topics), seconds)
    if publishers:
        return text + ('%s publishes it but sent nothing: is the filter '
                       'getting its sensors?' % ', '.join(sorted(publishers)))
    others = sorted(set(candidates or ()) - set(topics))
    if others:
        return text + ('nothing publishes it. Topics that carry '
                       'PoseWithCovarianceStamped: %s. Remap the input, e.g. '
                       'roslaunch rbx1_nav odom_ekf.launch input:=%s'
                       % (', '.join(others), others[0]))
    if candidates is None and publishers is None:
        return text + 'whether anything publishes it is unknown (no master?)'
    return text + ('nothing publishes PoseWithCovarianceStamped at all: start '
                   'pose_ekf.py (or robot_pose_ekf) first')
