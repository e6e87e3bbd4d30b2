"""Planar pose filter, the maths behind ``pose_ekf.py`` (robot_pose_ekf's job).

The filter estimates the robot's pose ``(x, y, yaw)`` in the output frame
with an extended Kalman filter:

* **Predict** with the wheel-odometry increment since the last step: the
  body-frame motion ``(dx, dy, dyaw)`` between two odometry poses, composed
  onto the estimate. The covariance grows by the increment's covariance.
  Without odometry, visual odometry's increments predict in the same way.
* **Relative updates**: the change of the gyro's yaw since its last fused
  reading measures the change of the estimated yaw since then; the change
  of the visual odometry pose (while wheel odometry drives the prediction)
  measures the body-frame motion since then. The filter keeps a copy of the
  pose at each such sensor's last update (a stochastic clone) jointly with
  the current pose, so these relative measurements are fused exactly.
* **Absolute updates**: a GPS fix measures x, y plus the offset between the
  GPS frame and the output frame. That offset joins the state at the first
  fix (so the GPS is read "relative to where the filter started") and every
  later fix refines it and the pose, weighted by the fix's covariance. The
  GPS frame's axes are taken to be the output frame's; z is ignored.

As in robot_pose_ekf, the odometry, gyro and visual odometry covariances
are read as the covariance of that sensor's change between two filter
steps; a GPS covariance is the fix's own (m^2).
An odometry step with no wheel motion adds no uncertainty, so a robot at
rest keeps its pose instead of following the gyro's drift.
Without odometry or visual odometry (only the gyro) the prediction
is "no motion" with a large variance, so the yaw follows the gyro and the
position stays put. :class:`GyroOdomFusion` adds start-up and sensor
timeouts on top of :class:`PlanarEkf`, drops bad input through
:class:`rbx1_nav.input_check.InputCheck` (unstamped, out of order, NaN or
absurd readings, negative variances), restarts itself should its estimate
ever stop being finite or ROS time move backwards, and describes its state
(:meth:`GyroOdomFusion.status_text`). :class:`OtherPublisherWatch`
spots a second publisher of the filter's transform. No rospy here: times
are float seconds, poses are plain tuples.
"""
import collections
import math

import numpy as np

from rbx1_nav.input_check import (GPS_JUMP, MAX_POSITION, MAX_VARIANCE,
                                  OTHER_CLOCK, ZERO_VARIANCE, ClockWatch,
                                  InputCheck)
from rbx1_nav.transform_utils import normalize_angle

__all__ = ['PlanarEkf', 'SensorWatch', 'GyroOdomFusion', 'odom_increment',
           'pose_covariance_3x3', 'position_covariance_2x2', 'covariance_6x6',
           'is_finite_estimate', 'silent_sensor_text', 'OtherPublisherWatch',
           'other_publisher_text', 'SENSORS', 'MIN_VARIANCE', 'MAX_VARIANCE',
           'MAX_POSITION']

#: Variances are floored here so a sensor reporting zero covariance (as the
#: ArbotiX fake robot does) is trusted completely without a singular matrix.
MIN_VARIANCE = 1e-9
#: Growth rate of the motion variance when no odometry is fused, per second:
#: x and y (m^2/s) and yaw (rad^2/s). Large, so the gyro decides the yaw.
NO_ODOM_VARIANCE_RATE = np.array([1.0, 1.0, 10.0])
#: Odometry increments smaller than this (m, rad) mean the wheels did not
#: turn: such a step adds no uncertainty, so a robot at rest keeps its pose
#: and covariance and ignores gyro drift (a zero-velocity update).
AT_REST = 1e-9
#: Variance reported for z, roll and pitch, which the planar model fixes.
PLANAR_FIXED_VARIANCE = 1e-9
_POSE_INDICES = (0, 1, 5)  # x, y, yaw rows of a 6x6 ROS pose covariance
#: A variance at or above this (m^2, rad^2), -1 or infinity is a driver's
#: "do not use this component" (1e6 in robot_pose_ekf's users, 1e10 and
#: 1e308 in Kobuki's, DBL_MAX in others): the component is left unmeasured,
#: never fused as a number (a sd of 316 m or 316 rad means nothing anyway).
UNMEASURED_VARIANCE = 1e5
#: GPS in robot_pose_ekf's mode: a fix farther than this many standard
#: deviations (of the fix and the estimate together) from the prediction is
#: dropped as a jump, not fused.
GPS_GATE_SIGMAS = 10.0
#: A GPS stamp farther than this from ROS time (s) is from another clock.
MAX_STAMP_SKEW = 10.0
#: Readings kept per sensor, to read each at the filter's time (GPS mode).
HISTORY = 100
_AXES = {'odom': ('x', 'y', 'yaw'), 'vo': ('x', 'y', 'yaw'), 'imu': ('yaw',),
         'gps': ('x', 'y')}


def unmeasured_components(cov):
    """``(cleaned, mask)`` for a sensor covariance.

    ``mask[i]`` is True where variance ``i`` says "not measured" (at least
    :data:`UNMEASURED_VARIANCE`, exactly -1, or +infinity); ``cleaned`` is
    ``cov`` with those rows and columns zeroed, ready for the input check.
    """
    cov = np.array(cov, dtype=float, ndmin=2)
    diag = np.diag(cov)
    with np.errstate(invalid='ignore'):
        mask = (diag >= UNMEASURED_VARIANCE) | (diag == -1.0)
    cleaned = cov.copy()
    cleaned[mask, :] = 0.0
    cleaned[:, mask] = 0.0
    return cleaned, mask


def odom_increment(previous, current):
    """Body-frame motion ``(dx, dy, dyaw)`` from pose ``previous`` to ``current``.

    Poses are ``(x, y, yaw)``; ``dx, dy`` are in the frame of ``previous``
    so the increment composes onto any other estimate of that pose.
    Raises ValueError if the increment is not finite (poses so far apart
    that their difference overflows).
    """
    px, py, pyaw = previous
    cx, cy, cyaw = current
    c, s = math.cos(pyaw), math.sin(pyaw)
    dx, dy = cx - px, cy - py
    increment = (c * dx + s * dy, -s * dx + c * dy, cyaw - pyaw)
    if not all(math.isfinite(v) for v in increment):
        raise ValueError('odometry increment is not finite')
    return increment[:2] + (normalize_angle(increment[2]),)


def pose_covariance_3x3(cov36):
    """The (x, y, yaw) block of a row-major 6x6 ROS covariance."""
    full = np.asarray(cov36, dtype=float).reshape(6, 6)
    return full[np.ix_(_POSE_INDICES, _POSE_INDICES)]


def position_covariance_2x2(cov36):
    """The (x, y) block of a row-major 6x6 ROS covariance."""
    return np.asarray(cov36, dtype=float).reshape(6, 6)[0:2, 0:2].copy()


def covariance_6x6(cov3):
    """Row-major 36-list: ``cov3`` on x, y, yaw; z, roll, pitch fixed."""
    full = np.diag([0.0, 0.0] + [PLANAR_FIXED_VARIANCE] * 3 + [0.0])
    full[np.ix_(_POSE_INDICES, _POSE_INDICES)] = cov3
    return [float(v) for v in full.ravel()]


def floored(cov):
    """Symmetric copy of ``cov`` with every variance at least MIN_VARIANCE."""
    cov = np.array(cov, dtype=float, ndmin=2)
    cov = 0.5 * cov + 0.5 * cov.T  # halve first: cov + cov.T may overflow
    diag = np.diag(cov)
    return cov + np.diag(np.maximum(MIN_VARIANCE - diag, 0.0))


class PlanarEkf(object):
    """EKF over ``(x, y, yaw)`` driven by motion increments.

    :meth:`predict` composes a body-frame increment onto the pose. Relative
    sensors (a gyro's yaw, visual odometry's pose) measure the change of the
    pose since their *anchor*: a copy of the pose taken at that sensor's
    previous update (:meth:`set_anchor`). Each anchor stays in the state
    (a "stochastic clone"), so the joint distribution of every anchor and the
    current pose is kept and a change spanning several predict steps is fused
    exactly. :meth:`add_offset` appends the 2-D offset between an absolute
    position sensor's frame (GPS) and the output frame, which
    :meth:`update_position` then refines with each fix.

    :attr:`mean` and :attr:`cov` are views of the pose part of the state
    (3 and 3x3); the whole state is :attr:`state` / :attr:`state_cov`.
    """

    def __init__(self, pose, covariance, anchors=('imu',)):
        self.state = np.array(pose, dtype=float)
        self.state_cov = floored(covariance)
        self._blocks = {'pose': (0, 3)}  # name -> (start, size)
        for name in anchors:
            self.set_anchor(name)

    # -- the pose part --------------------------------------------------------
    @property
    def mean(self):
        return self.state[0:3]

    @property
    def cov(self):
        return self.state_cov[0:3, 0:3]

    @property
    def pose(self):
        """``(x, y, yaw)`` with yaw in [-pi, pi]."""
        return (float(self.state[0]), float(self.state[1]),
                normalize_angle(self.state[2]))

    # -- state blocks ---------------------------------------------------------
    def _append(self, name, mean, cov, cross):
        """Append block ``name`` with its covariance and cross-covariance."""
        n, k = len(self.state), len(mean)
        new_cov = np.zeros((n + k, n + k))
        new_cov[:n, :n] = self.state_cov
        new_cov[n:, n:] = cov
        new_cov[n:, :n] = cross
        new_cov[:n, n:] = cross.T
        self.state = np.concatenate([self.state, mean])
        self.state_cov = new_cov
        self._blocks[name] = (n, k)

    def _remove(self, name):
        start, size = self._blocks.pop(name)
        keep = [i for i in range(len(self.state))
                if not start <= i < start + size]
        self.state = self.state[keep]
        self.state_cov = self.state_cov[np.ix_(keep, keep)]
        self._blocks = {b: (s - size if s > start else s, k)
                        for b, (s, k) in self._blocks.items()}

    def has_anchor(self, name='imu'):
        return ('anchor', name) in self._blocks

    def set_anchor(self, name='imu'):
        """Measure sensor ``name``'s next change from the current pose."""
        if self.has_anchor(name):
            self._remove(('anchor', name))
        self._append(('anchor', name), self.state[0:3].copy(),
                     self.state_cov[0:3, 0:3].copy(),
                     self.state_cov[0:3, :].copy())

    def drop_anchor(self, name='imu'):
        """Forget sensor ``name``'s anchor (it is gone); updates need a new one."""
        if self.has_anchor(name):
            self._remove(('anchor', name))

    def _anchor_index(self, name):
        if not self.has_anchor(name):
            raise RuntimeError('an update from %s needs its anchor' % name)
        return self._blocks[('anchor', name)][0]

    # -- predict and update ---------------------------------------------------
    def predict(self, increment, increment_cov):
        """Move by body-frame ``increment`` (dx, dy, dyaw) with covariance."""
        x, y, yaw = self.state[0:3]
        ux, uy, uyaw = increment
        c, s = math.cos(yaw), math.sin(yaw)
        n = len(self.state)
        jac_state = np.eye(n)
        jac_state[0, 2] = -s * ux - c * uy
        jac_state[1, 2] = c * ux - s * uy
        jac_motion = np.zeros((n, 3))
        jac_motion[0:3, 0:3] = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
        self.state[0:3] = (x + c * ux - s * uy, y + s * ux + c * uy, yaw + uyaw)
        self.state_cov = (jac_state @ self.state_cov @ jac_state.T
                          + jac_motion @ floored(increment_cov) @ jac_motion.T)

    def _update(self, jac, innovation, noise):
        """Kalman update of the whole state: ``jac`` (m x n), noise (m x m)."""
        cov = self.state_cov
        gain_num = cov @ jac.T
        s = jac @ gain_num + floored(noise)
        gain = np.linalg.solve(s.T, gain_num.T).T  # gain_num @ inv(s)
        self.state = self.state + gain @ innovation
        cov = cov - gain @ s @ gain.T
        self.state_cov = 0.5 * (cov + cov.T)

    def update_yaw_increment(self, dyaw, variance, name='imu'):
        """Fuse a measured yaw change ``dyaw`` since the anchor; re-anchor."""
        a = self._anchor_index(name)
        jac = np.zeros((1, len(self.state)))
        jac[0, 2], jac[0, a + 2] = 1.0, -1.0
        innovation = normalize_angle(dyaw - (self.state[2] - self.state[a + 2]))
        self._update(jac, np.array([innovation]),
                     [[max(float(variance), MIN_VARIANCE)]])
        self.set_anchor(name)

    def update_pose_increment(self, increment, increment_cov, name='vo',
                              rows=(0, 1, 2)):
        """Fuse a measured body-frame motion since the anchor; re-anchor.

        ``increment`` is ``(dx, dy, dyaw)`` in the frame of the anchor pose,
        as :func:`odom_increment` gives it for two poses of the sensor;
        ``rows`` picks the measured components.
        """
        rows = list(rows)
        a = self._anchor_index(name)
        ax, ay, ayaw = self.state[a:a + 3]
        x, y, yaw = self.state[0:3]
        c, s = math.cos(ayaw), math.sin(ayaw)
        dx, dy = x - ax, y - ay
        predicted = np.array([c * dx + s * dy, -s * dx + c * dy, yaw - ayaw])
        jac = np.zeros((3, len(self.state)))
        jac[0:3, 0:3] = [[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]]
        jac[0:3, a:a + 3] = [[-c, -s, -s * dx + c * dy],
                             [s, -c, -c * dx - s * dy],
                             [0.0, 0.0, -1.0]]
        innovation = np.asarray(increment, dtype=float) - predicted
        innovation[2] = normalize_angle(innovation[2])
        if rows:
            self._update(jac[rows], innovation[rows],
                         np.asarray(increment_cov)[np.ix_(rows, rows)])
        self.set_anchor(name)

    def update_yaw(self, yaw, variance):
        """Fuse an absolute yaw (an IMU's heading while GPS is active)."""
        jac = np.zeros((1, len(self.state)))
        jac[0, 2] = 1.0
        innovation = normalize_angle(yaw - self.state[2])
        self._update(jac, np.array([innovation]),
                     [[max(float(variance), MIN_VARIANCE)]])

    def blend_position(self, position, position_cov, weights, rows=(0, 1)):
        """Move the pose's x, y a fraction ``weights`` (per axis) of the way
        to a fix, robot_pose_ekf's fixed-gain GPS update; the covariance
        is that of the estimator this makes (Joseph form)."""
        rows = list(rows)
        n = len(self.state)
        gain = np.zeros((n, 2))
        jac = np.zeros((2, n))
        for i in rows:
            gain[i, i], jac[i, i] = weights[i], 1.0
        innovation = np.asarray(position, dtype=float) - self.state[0:2]
        self.state = self.state + gain @ innovation
        keep = np.eye(n) - gain @ jac
        cov = (keep @ self.state_cov @ keep.T
               + gain @ floored(position_cov) @ gain.T)
        self.state_cov = 0.5 * (cov + cov.T)

    def position_distance(self, position, position_cov, rows=(0, 1)):
        """Mahalanobis distance of a fix ``(x, y)`` from the pose's x, y,
        on the measured axes ``rows``."""
        rows = list(rows)
        s = (self.state_cov[0:2, 0:2] + floored(position_cov))[
            np.ix_(rows, rows)]
        d = (np.asarray(position, dtype=float) - self.state[0:2])[rows]
        return math.sqrt(max(float(d @ np.linalg.solve(s, d)), 0.0))

    def update_position(self, position, position_cov, rows=(0, 1)):
        """Fuse an absolute fix of the pose's x, y (the GPS frame is the
        output frame); ``rows`` picks the measured axes (0 x, 1 y)."""
        rows = list(rows)
        jac = np.zeros((2, len(self.state)))
        jac[0, 0] = jac[1, 1] = 1.0
        innovation = np.asarray(position, dtype=float) - self.state[0:2]
        self._update(jac[rows], innovation[rows],
                     np.asarray(position_cov)[np.ix_(rows, rows)])


class SensorWatch(object):
    """Tracks whether a sensor is fresh: seen within ``timeout`` seconds."""

    def __init__(self, name, timeout):
        self.name = name
        self.timeout = float(timeout)
        self.last_seen = None
        self.last_stamp = None
        self.active = False
        self.ever_active = False
        self.lost_at = None

    def seen(self, now, stamp=None):
        """Record a message received at time ``now`` (seconds)."""
        self.last_seen = now
        self.last_stamp = stamp

    def check(self, now):
        """Update :attr:`active`; return 'started', 'back', 'lost' or None."""
        fresh = (self.last_seen is not None
                 and now - self.last_seen <= self.timeout)
        if fresh and not self.active:
            self.active = True
            self.lost_at = None
            event = 'back' if self.ever_active else 'started'
            self.ever_active = True
            return event
        if self.active and not fresh:
            self.active = False
            self.lost_at = now
            return 'lost'
        return None

    def describe(self, now):
        """'active', 'waiting (never received)' or 'dropped (...)'."""
        if self.active:
            return 'active'
        if self.last_seen is None:
            return 'waiting (no message received yet)'
        return 'dropped (no message for %.2f s)' % (now - self.last_seen)


class _Reading(object):
    """One validated sensor message: its stamp, value and covariance."""

    def __init__(self, stamp, value, cov, seq, unmeasured):
        self.stamp, self.value, self.cov, self.seq = stamp, value, cov, seq
        #: components whose variance said "not measured"
        self.unmeasured = unmeasured

    @property
    def measured(self):
        """Indices of the measured components."""
        return [i for i, m in enumerate(self.unmeasured) if not m]


#: Every sensor the filter knows, in robot_pose_ekf's order.
SENSORS = ('odom', 'imu', 'vo', 'gps')
#: Sensors whose motion can drive the prediction, by preference.
_MOTION_SOURCES = ('odom', 'vo')
#: What each sensor measures, for the status text.
SENSOR_KINDS = {'odom': 'wheel odometry, relative pose',
                'imu': 'gyro yaw, relative',
                'vo': 'visual odometry, relative pose',
                'gps': 'absolute x, y in the output frame'}


def _no_motion_cov(dt):
    """Covariance of a step of ``dt`` seconds with no motion sensor."""
    return np.diag(NO_ODOM_VARIANCE_RATE * max(dt, 1e-3))


def _increment_cov(increment, reading, dt, scale=1.0):
    """Covariance of a motion ``increment`` read from ``reading``.

    None at rest (wheels still: a zero-velocity update); the reading's
    covariance times ``scale`` otherwise, its unmeasured components
    replaced by the no-motion-sensor growth over ``dt``.
    """
    if max(abs(v) for v in increment) < AT_REST:
        return np.zeros((3, 3))
    cov = reading.cov * scale
    unmeasured = np.asarray(reading.unmeasured, dtype=bool)
    cov[unmeasured, unmeasured] = np.diag(_no_motion_cov(dt))[unmeasured]
    return cov


class GyroOdomFusion(object):
    """The whole robot_pose_ekf-like fusion, fed plain values.

    Sensors: wheel odometry (``odom``), a gyro's yaw (``imu``), visual
    odometry (``vo``) and GPS (``gps``). The first active of odometry and
    visual odometry drives the prediction with its increments; the gyro and
    (while odometry drives) visual odometry are fused as relative
    measurements of the motion since their previous update; GPS fixes are
    absolute x, y measurements in a frame whose origin the filter learns
    from the first fix (z is ignored, the axes are taken to be the output
    frame's).

    Call :meth:`add_odom` / :meth:`add_imu` / :meth:`add_vo` /
    :meth:`add_gps` per message and :meth:`step` at the filter rate.
    :meth:`step` returns log events ``(level, text)``; after it,
    :attr:`estimate` is ``(stamp, pose, cov3)`` or None, and :attr:`updated`
    says whether this step fused new data. Should a step ever leave a
    non-finite estimate, the filter :meth:`restart` s (with a warning event)
    instead of reporting it.

    Every reading passes :attr:`inputs` (an
    :class:`rbx1_nav.input_check.InputCheck`): an unstamped, out-of-order,
    repeated, NaN or absurd reading raises
    :class:`rbx1_nav.input_check.RejectedInput` and is not kept, so the
    estimate's stamp never goes back. Call :meth:`check_clock` with the
    current ROS time before each reading and step: should it move
    backwards, the filter restarts from the next readings on the new clock.
    """

    def __init__(self, odom_used=True, imu_used=True, sensor_timeout=1.0,
                 vo_used=False, gps_used=False, topics=None,
                 gps_kalman=False):
        if not (odom_used or imu_used or vo_used):
            raise ValueError('at least one of odom_used, imu_used and vo_used '
                             'is needed (GPS alone gives no heading)')
        self.odom_used, self.imu_used = bool(odom_used), bool(imu_used)
        self.vo_used, self.gps_used = bool(vo_used), bool(gps_used)
        self.gps_kalman = bool(gps_kalman)
        self.sensor_timeout = sensor_timeout
        self._seq = 0
        self.started_at = None  # time of the first step: start-up
        self._silent_reported = set()
        self.restarts = 0
        self.inputs = InputCheck()
        self._clock = ClockWatch()
        self.stamp = None
        #: sensor -> topic, for the texts
        self.topics = dict(topics or {})
        self._noted = set()  # (sensor, unmeasured mask) already noted
        self._notes = []  # notes for the next step's events
        self.restart()

    def restart(self, new_clock=False):
        """Forget the estimate and every reading received so far.

        The filter starts again like a new one: from the next odometry
        message (without odometry, from the next visual odometry or IMU
        message). Its readings and its estimate must still be newer than
        the last ones, unless ``new_clock`` (ROS time moved backwards):
        then the next readings are taken whatever their stamps.
        """
        self.watches = {name: SensorWatch(name, self.sensor_timeout)
                        for name in SENSORS}
        self._latest = dict.fromkeys(SENSORS)
        self._history = {name: collections.deque(maxlen=HISTORY)
                         for name in SENSORS}
        self._ref = dict.fromkeys(SENSORS)
        self._time = None  # GPS mode: the filter's time (s)
        self._was_active = set()  # GPS mode: sensors active at that time
        self._gps_fused = None  # GPS mode: stamp of the last fix used
        self._last_predict = None
        self.ekf = None
        self.updated = False
        if new_clock:
            self.stamp = None
            self.inputs.new_clock()

    def check_clock(self, now):
        """Seconds ROS time moved back since the previous call, or 0.0.

        On a move back (a bag looping, a simulator restarted) the filter
        restarts on the new clock at once, and start-up is ``now``.
        """
        back = self._clock.moved_back(now)
        if back > 0.0:
            self.restart(new_clock=True)
            self.restarts += 1
            self.started_at = now
        return back

    @property
    def estimate(self):
        """``(stamp, (x, y, yaw), cov3)`` or None before the filter starts."""
        if self.ekf is None:
            return None
        return self.stamp, self.ekf.pose, self.ekf.cov.copy()

    # -- input ----------------------------------------------------------------
    def add_odom(self, now, stamp, pose, cov3):
        """An odometry pose ``(x, y, yaw)`` stamped ``stamp`` with its 3x3
        covariance, received at ``now``.

        Raises RejectedInput (a ValueError) and keeps nothing for a zero,
        repeated or older stamp than the last odometry's, a NaN pose or
        covariance, a negative variance, a position beyond
        :data:`MAX_POSITION` or a covariance entry beyond
        :data:`MAX_VARIANCE`.
        """
        self._add_pose('odom', now, stamp, pose, cov3)

    def add_vo(self, now, stamp, pose, cov3):
        """A visual odometry pose ``(x, y, yaw)`` with its 3x3 covariance.

        Checked like :meth:`add_odom`; fused through its own increments.
        """
        self._add_pose('vo', now, stamp, pose, cov3)

    def add_imu(self, now, stamp, yaw, variance):
        """An IMU yaw (radians) with its variance; checked like
        :meth:`add_odom`."""
        cov, mask = self._screen('imu', [[variance]])
        if self._taken('imu', stamp, angles=(yaw,), covariance=cov):
            self._add('imu', now, stamp, normalize_angle(yaw),
                      floored(cov)[0, 0], mask)

    def add_gps(self, now, stamp, position, cov2):
        """A GPS fix ``(x, y)`` in metres with its 2x2 covariance; checked
        like :meth:`add_odom`, and dropped too for a zero variance (a GPS
        never knows its position exactly) or a stamp more than
        :data:`MAX_STAMP_SKEW` from ``now`` (another clock)."""
        x, y = (float(v) for v in position)
        cov, mask = self._screen('gps', cov2)
        if not self.used('gps'):
            return
        measured = np.diag(cov)[~mask]
        if np.any(measured == 0.0):
            raise self.inputs.reject('gps', ZERO_VARIANCE, (
                'the fix\'s covariance has a zero variance: no GPS knows '
                'its position exactly (set its real covariance)'))
        if abs(stamp - now) > MAX_STAMP_SKEW:
            raise self.inputs.reject('gps', OTHER_CLOCK, (
                'stamp %.3f s is %.1f s from ROS time %.3f s: the GPS stamps '
                'with another clock (stamp with ROS time)' % (
                    stamp, stamp - now, now)))
        if self._taken('gps', stamp, position=(x, y), covariance=cov):
            self._add('gps', now, stamp, (x, y), floored(cov), mask)

    def _add_pose(self, name, now, stamp, pose, cov3):
        x, y, yaw = (float(v) for v in pose)
        cov, mask = self._screen(name, cov3)
        if self._taken(name, stamp, position=(x, y), angles=(yaw,),
                       covariance=cov):
            self._add(name, now, stamp, (x, y, normalize_angle(yaw)),
                      floored(cov), mask)

    def _screen(self, name, cov):
        """Split off the unmeasured components of a sensor covariance;
        note (once per sensor and set of components) which they are."""
        cleaned, mask = unmeasured_components(cov)
        key = (name, tuple(mask))
        if mask.any() and self.used(name) and key not in self._noted:
            self._noted.add(key)
            axes = [a for a, m in zip(_AXES[name], mask) if m]
            values = ['%g' % v for v, m in zip(np.diag(
                np.array(cov, dtype=float, ndmin=2)), mask) if m]
            self._notes.append(('info', '%s on %s: variance %s of %s means '
                                '"not measured" (at least %g, -1 or inf): '
                                '%s not fused from it' % (
                                    name, self.topics.get(name, name),
                                    ', '.join(values), ', '.join(axes),
                                    UNMEASURED_VARIANCE, ', '.join(axes))))
        return cleaned, mask

    def _taken(self, name, stamp, **values):
        """False for an unused sensor; raises RejectedInput for a bad
        reading (:meth:`InputCheck.check`)."""
        if not self.used(name):
            return False
        self.inputs.check(name, stamp, **values)
        return True

    def _add(self, name, now, stamp, value, cov, unmeasured):
        self._seq += 1
        reading = _Reading(stamp, value, cov, self._seq, unmeasured)
        self._latest[name] = reading
        self._history[name].append(reading)
        self.watches[name].seen(now, stamp)

    def used(self, name):
        """Whether sensor ``name`` is used (its ``<name>_used`` flag)."""
        return getattr(self, name + '_used')

    def _used(self):
        return [n for n in SENSORS if self.used(n)]

    # -- the filter step ------------------------------------------------------
    def _driver(self, active):
        """The sensor whose messages step the filter, or None."""
        for name in _MOTION_SOURCES + ('imu',):
            if name in active:
                return name
        return None

    def step(self, now):
        """Run one filter step at time ``now``; return log events.

        With odometry active the filter steps on each new odometry message
        (the other sensors' news is fused with it); without odometry on
        each new visual odometry message, and without either on each new
        IMU message.
        """
        if self.started_at is None:
            self.started_at = now
        events, self._notes = self._notes + self._check_sensors(now), []
        self.updated = False
        active = [n for n in self._used() if self.watches[n].active]
        if self.gps_used:
            return events + self._step_gps_mode(now, active)
        if self.ekf is None:
            self._last_predict = now
            return events + self._try_start(active)
        driver = self._driver(active)
        if driver is None or not self._fresh(driver):
            return events
        fresh = [n for n in active if self._fresh(n)]
        try:
            with np.errstate(over='ignore', invalid='ignore'):
                events += self._fuse(now, driver, active, fresh)
        except (ValueError, np.linalg.LinAlgError) as err:
            return events + self._restarted(err)
        self._advance_stamp(active)
        return events

    def _restarted(self, err):
        """Restart after ``err``; the warning event to log."""
        self.restart()
        self.restarts += 1
        return [('warn', 'filter restarted: %s; it starts again from the '
                 'next %s message' % (err, self._start_sensor_text()))]

    # -- robot_pose_ekf's GPS mode (gps_used) ----------------------------------
    def _step_gps_mode(self, now, active):
        """One step with ``gps_used``, as robot_pose_ekf does.

        The filter starts when both the IMU and GPS are active, at the fix
        and the IMU's heading: its output frame is the GPS frame, with the
        IMU's yaw taken as heading in it. Each step runs at the filter's
        time, the oldest of the active sensors' newest stamps, where every
        sensor is read by interpolation: odometry (and visual odometry)
        increments since the last step, the IMU's yaw as absolute while GPS
        is active (relative otherwise), and each new fix once on x, y (the
        first after GPS starts or returns is skipped).
        """
        if self.ekf is None:
            return self._start_gps_mode(active)
        if not active:
            return []
        t = min([now] + [self._latest[n].stamp for n in active])
        if t <= self._time:
            return []
        # With gps_kalman, step at each new fix's own stamp on the way.
        times = sorted(set([t] + [r.stamp for r in self._history['gps']
                                  if self.gps_kalman and 'gps' in active
                                  and self._time < r.stamp < t]))
        events = []
        try:
            with np.errstate(over='ignore', invalid='ignore'):
                for step_time in times:
                    events += self._fuse_at(step_time, active)
                    self._time = step_time
                    self._was_active = set(active)
        except (ValueError, np.linalg.LinAlgError) as err:
            return self._restarted(err)
        if self.stamp is None or t > self.stamp:
            self.stamp, self.updated = t, True
        return events

    def _start_gps_mode(self, active):
        if 'imu' not in active or 'gps' not in active:
            return []
        fix, imu = self._latest['gps'], self._latest['imu']
        if len(fix.measured) < 2 or not imu.measured:
            return []  # noted once when it came in
        t = fix.stamp
        yaw = self._value_at('imu', t)
        cov = np.zeros((3, 3))
        cov[0:2, 0:2], cov[2, 2] = fix.cov, imu.cov
        self.ekf = PlanarEkf(fix.value + (yaw,), cov, anchors=())
        self._time, self._gps_fused = t, t  # this fix is used up
        self._was_active = set(active)
        for name in active:
            self._ref[name] = self._value_at(name, t)
        if self.stamp is None or t > self.stamp:
            self.stamp, self.updated = t, True
        return [('info', 'filter started at the GPS fix and the IMU heading '
                 '(gps_used: the output frame is the GPS frame): x=%.3f '
                 'y=%.3f yaw=%.3f' % self.ekf.pose)]

    def _fuse_at(self, t, active):
        """Predict to filter time ``t`` and fuse every active sensor there."""
        dt = t - self._time
        events = []
        now = {n: self._value_at(n, t) for n in active}
        ref = {n: self._ref[n] if n in self._was_active else None
               for n in SENSORS}
        if 'odom' in active and ref['odom'] is not None:
            increment = odom_increment(ref['odom'], now['odom'])
            self.ekf.predict(increment, _increment_cov(
                increment, self._latest['odom'], dt,
                scale=dt / self._period('odom', dt)))
        else:
            self.ekf.predict((0.0, 0.0, 0.0), _no_motion_cov(dt))
        self._check_finite()
        imu, vo = self._latest['imu'], self._latest['vo']
        if 'imu' in active and imu.measured and 'gps' in active:
            self.ekf.update_yaw(now['imu'], imu.cov)
        elif ('imu' in active and imu.measured and ref['imu'] is not None
              and self.ekf.has_anchor('imu')):
            self.ekf.update_yaw_increment(
                normalize_angle(now['imu'] - ref['imu']), imu.cov)
        if 'vo' in active and ref['vo'] is not None and self.ekf.has_anchor(
                'vo'):
            self.ekf.update_pose_increment(
                odom_increment(ref['vo'], now['vo']),
                vo.cov * (dt / self._period('vo', dt)), 'vo', vo.measured)
        for name in ('imu', 'vo'):
            (self.ekf.set_anchor if name in active
             else self.ekf.drop_anchor)(name)
        self._check_finite()
        if 'gps' in active:
            events += self._fuse_fix(t, ref['gps'] is None)
        else:
            self._gps_fused = None
        self._ref.update(now)
        return events

    def _fuse_fix(self, t, first):
        """Fuse the GPS position at ``t``; the first step after GPS starts
        or returns only reads it.

        As robot_pose_ekf: at every step, the fix (read at ``t``) pulls the
        position by the weight its covariance has against odometry's. With
        ``gps_kalman``: each fix once, with the Kalman gain.
        """
        if first:
            self._gps_fused = self._latest['gps'].stamp
            return []
        if self.gps_kalman:
            fix = next(r for r in reversed(self._history['gps'])
                       if r.stamp <= t)
            if fix.stamp <= self._gps_fused:
                return []
            self._gps_fused, position = fix.stamp, fix.value
        else:
            fix, position = self._latest['gps'], self._value_at('gps', t)
        if not fix.measured:
            return []
        distance = self.ekf.position_distance(position, fix.cov,
                                              fix.measured)
        if distance > GPS_GATE_SIGMAS:
            x, y, _ = self.ekf.pose
            text = self.inputs.warning(self.inputs.reject(
                'gps', GPS_JUMP, 'fix (%.2f, %.2f) is %.1f m (%.0f sd) from '
                'the estimate (%.2f, %.2f): not fused' % (
                    position + (math.hypot(position[0] - x, position[1] - y),
                                distance, x, y))), t,
                'gps on %s' % self.topics.get('gps', 'gps'))
            return [('warn', text)] if text else []
        if self.gps_kalman:
            self.ekf.update_position(position, fix.cov, fix.measured)
        else:
            odom = self._latest['odom']
            motion = (np.diag(odom.cov)[0:2] if 'odom' in self._was_active
                      else NO_ODOM_VARIANCE_RATE[0:2])
            self.ekf.blend_position(position, fix.cov,
                                    motion / (motion + np.diag(fix.cov)),
                                    fix.measured)
        self._check_finite()
        return []

    def _value_at(self, name, t):
        """Sensor ``name``'s value at time ``t``, interpolated between the
        two readings around it (the nearest one outside them)."""
        history = self._history[name]
        after = None
        for before in reversed(history):
            if before.stamp <= t:
                break
            after = before
        else:
            return history[0].value
        if after is None or before.stamp == t:
            return before.value
        f = (t - before.stamp) / (after.stamp - before.stamp)
        b = np.atleast_1d(before.value)
        d = np.atleast_1d(after.value) - b
        if name != 'gps':  # the last component is a yaw
            d[-1] = normalize_angle(d[-1])
        value = [float(v) for v in b + f * d]
        if name != 'gps':
            value[-1] = normalize_angle(value[-1])
        return value[0] if name == 'imu' else tuple(value)

    def _period(self, name, default):
        """Mean interval of sensor ``name``'s recent readings (s)."""
        history = self._history[name]
        if len(history) < 2:
            return max(default, 1e-6)
        return max((history[-1].stamp - history[0].stamp)
                   / (len(history) - 1), 1e-6)

    def _fresh(self, name):
        ref = self._ref[name]
        return ref is None or self._latest[name].seq != ref.seq

    def _start_sensor_text(self):
        if self.gps_used:
            return 'IMU and GPS'
        if self.odom_used:
            return 'odometry'
        return 'visual odometry' if self.vo_used else 'IMU'

    def _fuse(self, now, driver, active, fresh):
        """Predict to ``now`` with the driver; fuse the others' news."""
        events = []
        self._predict(driver, max(now - self._last_predict, 0.0))
        self._last_predict = now
        self._check_finite()
        for name in ('imu', 'vo'):
            relative = name in active and (name == 'imu' or name != driver)
            if not relative:
                self.ekf.drop_anchor(name)
                continue
            reading = self._latest[name]
            if not self.ekf.has_anchor(name) or self._ref[name] is None:
                # A new anchor: measure from here on (e.g. visual odometry
                # after odometry came back and took over the prediction).
                self._ref[name] = reading
                self.ekf.set_anchor(name)
                continue
            if name not in fresh:
                continue
            if not reading.measured:
                self.ekf.set_anchor(name)  # nothing measured: re-anchor
            elif name == 'imu':
                self.ekf.update_yaw_increment(
                    normalize_angle(reading.value - self._ref[name].value),
                    reading.cov, name)
            else:
                self.ekf.update_pose_increment(
                    odom_increment(self._ref[name].value, reading.value),
                    reading.cov, name, reading.measured)
            self._ref[name] = reading
            self._check_finite()
        return events

    def _check_finite(self):
        """ValueError unless the filter's mean and covariance are finite."""
        if not (np.all(np.isfinite(self.ekf.state))
                and np.all(np.isfinite(self.ekf.state_cov))):
            raise ValueError('the estimate is no longer finite')

    def _check_sensors(self, now):
        """Apply timeouts: a lost sensor is left out, a returning one re-based."""
        events = []
        for name in self._used():
            change = self.watches[name].check(now)
            if change == 'lost':
                self._ref[name] = None
                if self.ekf is not None:
                    self.ekf.drop_anchor(name)
                events.append(('warn', '%s timed out: no message for %.2f s; '
                               'fusing without it' % (
                                   name, self.watches[name].timeout)))
            elif change in ('started', 'back'):
                # A returning sensor starts a new reference: its jump while
                # away (e.g. a restarted driver) is never fused. GPS is
                # absolute: its frame origin stays valid.
                self._ref[name] = (None if name == 'gps'
                                   else self._latest[name])
                if name in ('imu', 'vo') and self.ekf is not None:
                    self.ekf.set_anchor(name)
                if change == 'back':
                    events.append(('info', '%s is back; fusing it again'
                                   % name))
        return events

    def _try_start(self, active):
        """Start at the first odometry (else visual odometry, else IMU)."""
        source = next((n for n in _MOTION_SOURCES if self.used(n)), None)
        if source is not None:
            if source not in active:
                return []
            # The output frame starts at this pose: known exactly, whatever
            # the sensor's own uncertainty of it.
            first = self._latest[source]
            self.ekf = PlanarEkf(first.value, np.zeros((3, 3)), anchors=())
            where = 'the first %s pose' % (
                'odometry' if source == 'odom' else 'visual odometry')
        else:
            if 'imu' not in active:
                return []
            self.ekf = PlanarEkf((0.0, 0.0, 0.0), np.zeros((3, 3)), anchors=())
            where = 'the origin (no odometry used)'
        for name in active:
            self._ref[name] = self._latest[name]
            if name == 'imu' or (name == 'vo' and source != 'vo'):
                self.ekf.set_anchor(name)
        self._advance_stamp(active)
        x, y, yaw = self.ekf.pose
        return [('info', 'filter started at %s: x=%.3f y=%.3f yaw=%.3f'
                 % (where, x, y, yaw))]

    def _predict(self, driver, dt):
        """Predict with the driver's increment, or 'no motion' without one."""
        if driver in _MOTION_SOURCES:
            reading, ref = self._latest[driver], self._ref[driver]
            increment = odom_increment(ref.value, reading.value)
            # An unmeasured component grows over the time the increment
            # spans (its two stamps), not over the filter's step: when
            # the step falls between two messages must not matter.
            self.ekf.predict(increment, _increment_cov(
                increment, reading, reading.stamp - ref.stamp))
            self._ref[driver] = reading
        else:
            self.ekf.predict((0.0, 0.0, 0.0), _no_motion_cov(dt))

    def _advance_stamp(self, active):
        """Stamp the estimate with the newest fused message; note progress.

        The stamp never goes back, not even across a :meth:`restart` (only
        on a new clock): an estimate no newer than the last is not news.
        """
        stamp = max(self._latest[n].stamp for n in active)
        if self.stamp is None or stamp > self.stamp:
            self.stamp = stamp
            self.updated = True

    # -- start-up checks and status -------------------------------------------
    def start(self, now):
        """Mark start-up at ``now`` (the first :meth:`step` does otherwise):
        a node calls it before it connects its topics, so the time that
        takes counts towards ``sensor_timeout``."""
        if self.started_at is None:
            self.started_at = now

    def silent_sensors(self, now):
        """Used sensors with no message ``sensor_timeout`` after start-up.

        Start-up is :meth:`start` or the first :meth:`step`. Each sensor is returned once,
        at the first call past that time; the caller warns about it.
        """
        if self.started_at is None or now - self.started_at < self.sensor_timeout:
            return []
        silent = [n for n in self._used() if n not in self._silent_reported
                  and self.watches[n].last_seen is None]
        self._silent_reported.update(silent)
        return silent

    def state(self):
        """'waiting for odom, imu', 'running' or 'running; dropped: imu'."""
        used = self._used()
        if self.ekf is None:
            source = ('imu and gps' if self.gps_used else
                      next((n for n in _MOTION_SOURCES if self.used(n)), 'imu'))
            missing = [n for n in used if not self.watches[n].active]
            return 'waiting for %s to start (no data yet from: %s)' % (
                source, ', '.join(missing) or 'none')
        dropped = [n for n in used if self.watches[n].ever_active
                   and not self.watches[n].active]
        waiting = [n for n in used if not self.watches[n].ever_active]
        text = 'running'
        if dropped:
            text += '; dropped: ' + ', '.join(dropped)
        if waiting:
            text += '; never received: ' + ', '.join(waiting)
        return text

    def status_text(self, now, topics=None):
        """A human-readable status: state, each sensor, the estimate.

        ``topics`` maps sensor names to the topics they are read from.
        """
        topics = topics or {}
        lines = ['state: ' + self.state()]
        for name in SENSORS:
            where = ' on %s' % topics[name] if name in topics else ''
            if not self.used(name):
                lines.append('%s%s: not used' % (name, where))
                continue
            watch = self.watches[name]
            line = '%s%s (%s): %s' % (name, where, SENSOR_KINDS[name],
                                      watch.describe(now))
            if watch.last_seen is not None:
                line += ', last stamp %.3f, received %.2f s ago' % (
                    watch.last_stamp if watch.last_stamp is not None
                    else float('nan'), now - watch.last_seen)
            lines.append(line)
        if self.ekf is None:
            lines.append('estimate: none yet')
        else:
            x, y, yaw = self.ekf.pose
            lines.append('estimate at stamp %.3f: x=%.3f m y=%.3f m yaw=%.4f '
                         'rad' % (self.stamp, x, y, yaw))
            lines.append('covariance (x, y, yaw): %s' % _matrix_text(
                self.ekf.cov))
        lines.append('sensor_timeout %.3g s; filter restarts: %d'
                     % (self.sensor_timeout, self.restarts))
        return '\n'.join(lines)


def _matrix_text(matrix):
    return '[' + '; '.join(' '.join('%.3g' % v for v in row)
                           for row in np.asarray(matrix)) + ']'


def silent_sensor_text(name, topic, timeout, publishers):
    """The warning for a used sensor that never sent a message.

    ``publishers`` lists the nodes that publish ``topic`` (the node's
    subscriber is connected to them), or is None when that is unknown.
    """
    text = ('%s_used is true but no message came on %s within %.3g s of '
            'start-up; ' % (name, topic, timeout))
    if publishers is None:
        return text + 'whether anything publishes it is unknown'
    if not publishers:
        return text + ('nothing publishes %s: start the driver, or remap '
                       '%s to the topic it publishes, or set ~%s_used false'
                       % (topic, name if name != 'imu' else 'imu_data', name))
    return text + ('%s publishes it but sent nothing: check that node (a '
                   'sensor not yet started? a wrong message type?)'
                   % ', '.join(sorted(publishers)))


class OtherPublisherWatch(object):
    """Spots another node publishing the transform this node publishes.

    :meth:`seen` is called for each tf message carrying our child frame
    from another node; it returns True when an error is due: at once for
    a new publisher, then every ``period`` seconds while it lasts.
    :meth:`gone` returns the publishers not heard for ``quiet`` seconds
    (each once), so the caller can say the conflict ended.
    """

    def __init__(self, period=30.0, quiet=5.0):
        self.period, self.quiet = float(period), float(quiet)
        self._last_seen = {}
        self._last_report = {}

    def seen(self, caller, now):
        self._last_seen[caller] = now
        last = self._last_report.get(caller)
        if last is None or now - last >= self.period or now < last:
            self._last_report[caller] = now
            return True
        return False

    def gone(self, now):
        ended = [c for c, t in self._last_seen.items() if now - t > self.quiet]
        for caller in ended:
            del self._last_seen[caller]
            self._last_report.pop(caller, None)
        return ended

    @property
    def publishers(self):
        """Other publishers heard within ``quiet`` s, in name order."""
        return sorted(self._last_seen)


def other_publisher_text(caller, parent, child, topic):
    """The error logged while another node publishes our transform."""
    return ('node %s also publishes the transform %s -> %s on %s; with two '
            'publishers the robot\'s pose jumps between them. Fix: turn off '
            'that node\'s tf (a TurtleBot driver or fake_turtlebot: '
            'publish_tf: false), or give pose_ekf other frames '
            '(~output_frame, ~base_footprint_frame), or run pose_ekf as an '
            'estimator only (~publish_tf false)' % (caller, parent, child,
                                                     topic))


def is_finite_estimate(estimate):
    """True if ``estimate`` (``(stamp, pose, cov3)`` or None) is all finite.

    None (no estimate yet) counts as finite: there is nothing wrong to publish.
    """
    if estimate is None:
        return True
    _, pose, cov3 = estimate
    return (all(math.isfinite(v) for v in pose)
            and bool(np.all(np.isfinite(cov3))))
