"""Planar gyro + wheel-odometry pose filter, the maths behind ``pose_ekf.py``.

The filter estimates the robot's pose ``(x, y, yaw)`` in the output frame
with an extended Kalman filter:

* **Predict** with the wheel-odometry increment since the last step: the
  body-frame motion ``(dx, dy, dyaw)`` between two odometry poses, composed
  onto the estimate. The covariance grows by the increment's covariance.
* **Update** with the gyro: the change of the IMU's yaw since its last
  fused reading measures the change of the estimated yaw since then. The
  filter keeps the joint distribution of the pose at that reading and now,
  so this relative measurement is fused exactly; it shrinks the covariance
  the prediction added.

As in robot_pose_ekf, each sensor's reported covariance is read as the
covariance of that sensor's change between two filter steps, so the fusion
weights are the ratio of the odometry's and the gyro's yaw variances.
An odometry step with no wheel motion adds no uncertainty, so a robot at
rest keeps its pose instead of following the gyro's drift.
Without odometry (``odom_used`` false, or odometry timed out) the prediction
is "no motion" with a large variance, so the yaw follows the gyro and the
position stays put. :class:`GyroOdomFusion` adds start-up and sensor
timeouts on top of :class:`PlanarEkf`, rejects absurd input (a variance
above :data:`MAX_VARIANCE`, a position beyond :data:`MAX_POSITION`) and
restarts itself should its estimate ever stop being finite. No rospy here:
times are float seconds, poses are plain tuples.
"""
import math

import numpy as np

from rbx1_nav.transform_utils import normalize_angle

__all__ = ['PlanarEkf', 'SensorWatch', 'GyroOdomFusion', 'odom_increment',
           'pose_covariance_3x3', 'covariance_6x6', 'is_finite_estimate',
           'MIN_VARIANCE', 'MAX_VARIANCE', 'MAX_POSITION']

#: Variances are floored here so a sensor reporting zero covariance (as the
#: ArbotiX fake robot does) is trusted completely without a singular matrix.
MIN_VARIANCE = 1e-9
#: Sensor covariance entries above this (m^2, rad^2) are absurd: the message
#: is dropped. Far above any real sensor's, far below a float's range, so
#: the filter's sums and products of covariances stay finite.
MAX_VARIANCE = 1e12
#: Odometry positions farther than this from the origin (m) are absurd.
MAX_POSITION = 1e9
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

    :meth:`predict` composes a body-frame increment onto the pose;
    :meth:`update_yaw_increment` fuses a measured change of yaw since the
    *anchor*: the pose at the previous gyro update (or at :meth:`set_anchor`).
    The filter carries the joint distribution of anchor and current pose, so
    a yaw change spanning several predict steps is fused exactly.
    """

    def __init__(self, pose, covariance):
        self.mean = np.array(pose, dtype=float)
        self.cov = floored(covariance)
        self._anchor = None  # (mean, cov, cross-cov anchor x current)
        self.set_anchor()

    @property
    def pose(self):
        """``(x, y, yaw)`` with yaw in [-pi, pi]."""
        return (float(self.mean[0]), float(self.mean[1]),
                normalize_angle(self.mean[2]))

    def set_anchor(self):
        """Measure the next yaw change from the current pose."""
        self._anchor = (self.mean.copy(), self.cov.copy(), self.cov.copy())

    def drop_anchor(self):
        """Forget the anchor (the gyro is gone); updates need a new one."""
        self._anchor = None

    def predict(self, increment, increment_cov):
        """Move by body-frame ``increment`` (dx, dy, dyaw) with covariance."""
        x, y, yaw = self.mean
        ux, uy, uyaw = increment
        c, s = math.cos(yaw), math.sin(yaw)
        jac_state = np.array([[1.0, 0.0, -s * ux - c * uy],
                              [0.0, 1.0, c * ux - s * uy],
                              [0.0, 0.0, 1.0]])
        jac_motion = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        self.mean = np.array([x + c * ux - s * uy, y + s * ux + c * uy,
                              yaw + uyaw])
        self.cov = (jac_state @ self.cov @ jac_state.T
                    + jac_motion @ floored(increment_cov) @ jac_motion.T)
        if self._anchor is not None:
            a_mean, a_cov, cross = self._anchor
            self._anchor = (a_mean, a_cov, cross @ jac_state.T)

    def update_yaw_increment(self, dyaw, variance):
        """Fuse a measured yaw change ``dyaw`` since the anchor; re-anchor."""
        if self._anchor is None:
            raise RuntimeError('update_yaw_increment needs an anchor')
        a_mean, a_cov, cross = self._anchor
        mean = np.concatenate([a_mean, self.mean])
        cov = np.block([[a_cov, cross], [cross.T, self.cov]])
        h = np.array([0.0, 0.0, -1.0, 0.0, 0.0, 1.0])
        innovation = normalize_angle(dyaw - h @ mean)
        gain_num = cov @ h
        s = h @ gain_num + max(float(variance), MIN_VARIANCE)
        gain = gain_num / s
        mean = mean + gain * innovation
        cov = cov - np.outer(gain, gain) * s
        self.mean = mean[3:]
        self.cov = 0.5 * (cov[3:, 3:] + cov[3:, 3:].T)
        self.set_anchor()


class SensorWatch(object):
    """Tracks whether a sensor is fresh: seen within ``timeout`` seconds."""

    def __init__(self, name, timeout):
        self.name = name
        self.timeout = float(timeout)
        self.last_seen = None
        self.active = False
        self.ever_active = False

    def seen(self, now):
        """Record a message received at time ``now`` (seconds)."""
        self.last_seen = now

    def check(self, now):
        """Update :attr:`active`; return 'started', 'back', 'lost' or None."""
        fresh = (self.last_seen is not None
                 and now - self.last_seen <= self.timeout)
        if fresh and not self.active:
            self.active = True
            event = 'back' if self.ever_active else 'started'
            self.ever_active = True
            return event
        if self.active and not fresh:
            self.active = False
            return 'lost'
        return None


class _Reading(object):
    """One validated sensor message: its stamp, value and covariance."""

    def __init__(self, stamp, value, cov, seq):
        self.stamp, self.value, self.cov, self.seq = stamp, value, cov, seq


class GyroOdomFusion(object):
    """The whole robot_pose_ekf-like fusion, fed plain values.

    Call :meth:`add_odom` / :meth:`add_imu` per message and :meth:`step` at
    the filter rate. :meth:`step` returns log events ``(level, text)``;
    after it, :attr:`estimate` is ``(stamp, pose, cov3)`` or None, and
    :attr:`updated` says whether this step fused new data. Should a step
    ever leave a non-finite estimate, the filter :meth:`restart` s (with a
    warning event) instead of reporting it.
    """

    def __init__(self, odom_used=True, imu_used=True, sensor_timeout=1.0):
        if not (odom_used or imu_used):
            raise ValueError('at least one of odom_used and imu_used is needed')
        self.odom_used, self.imu_used = bool(odom_used), bool(imu_used)
        self.sensor_timeout = sensor_timeout
        self._seq = 0
        self.restart()

    def restart(self):
        """Forget the estimate and every reading received so far.

        The filter starts again like a new one: from the next odometry
        message (without odometry, from the next IMU message).
        """
        self.watches = {name: SensorWatch(name, self.sensor_timeout)
                        for name in ('odom', 'imu')}
        self._latest = {'odom': None, 'imu': None}
        self._ref = {'odom': None, 'imu': None}
        self._last_predict = None
        self.ekf = None
        self.stamp = None
        self.updated = False

    @property
    def estimate(self):
        """``(stamp, (x, y, yaw), cov3)`` or None before the first odometry."""
        if self.ekf is None:
            return None
        return self.stamp, self.ekf.pose, self.ekf.cov.copy()

    def add_odom(self, now, stamp, pose, cov3):
        """An odometry pose ``(x, y, yaw)`` with its 3x3 covariance.

        Raises ValueError (and keeps nothing) for a NaN pose or covariance,
        a position beyond :data:`MAX_POSITION` or a covariance entry beyond
        :data:`MAX_VARIANCE`.
        """
        x, y, yaw = (float(v) for v in pose)
        if not all(math.isfinite(v) for v in (x, y, yaw)):
            raise ValueError('odometry pose has a NaN or infinite component')
        if max(abs(x), abs(y)) > MAX_POSITION:
            raise ValueError('odometry position (%g, %g) is absurd: more than '
                             '%g m from the origin' % (x, y, MAX_POSITION))
        self._add('odom', now, stamp, (x, y, normalize_angle(yaw)),
                  _checked_cov(cov3))

    def add_imu(self, now, stamp, yaw, variance):
        """An IMU yaw (radians) with its variance; ValueError if unusable."""
        if not math.isfinite(yaw):
            raise ValueError('IMU yaw is NaN or infinite')
        self._add('imu', now, stamp, normalize_angle(yaw),
                  _checked_cov([[variance]])[0, 0])

    def _add(self, name, now, stamp, value, cov):
        if not getattr(self, name + '_used'):
            return
        self._seq += 1
        self._latest[name] = _Reading(stamp, value, cov, self._seq)
        self.watches[name].seen(now)

    def _used(self):
        return [n for n in ('odom', 'imu') if getattr(self, n + '_used')]

    def step(self, now):
        """Run one filter step at time ``now``; return log events.

        With odometry active the filter steps on each new odometry message
        (the gyro's change since its last fused reading is fused with it);
        without odometry it steps on each new IMU message.
        """
        events = self._check_sensors(now)
        self.updated = False
        active = [n for n in self._used() if self.watches[n].active]
        if self.ekf is None:
            self._last_predict = now
            return events + self._try_start(active)
        fresh = [n for n in active
                 if self._latest[n].seq != self._ref[n].seq]
        driver = 'odom' if 'odom' in active else 'imu'
        if driver not in fresh:
            return events
        try:
            with np.errstate(over='ignore', invalid='ignore'):
                self._fuse(now, fresh)
        except ValueError as err:
            self.restart()
            return events + [('warn', 'filter restarted: %s; it starts again '
                              'from the next %s message' % (
                                  err, 'odometry' if self.odom_used else 'IMU'))]
        self._advance_stamp(active)
        return events

    def _fuse(self, now, fresh):
        """Predict to ``now``; fuse the gyro's change if it is fresh."""
        self._predict(max(now - self._last_predict, 0.0))
        self._last_predict = now
        self._check_finite()
        if 'imu' in fresh:
            reading = self._latest['imu']
            self.ekf.update_yaw_increment(
                normalize_angle(reading.value - self._ref['imu'].value),
                reading.cov)
            self._ref['imu'] = reading
            self._check_finite()

    def _check_finite(self):
        """ValueError unless the filter's mean and covariance are finite."""
        if not (np.all(np.isfinite(self.ekf.mean))
                and np.all(np.isfinite(self.ekf.cov))):
            raise ValueError('the estimate is no longer finite')

    def _check_sensors(self, now):
        """Apply timeouts: a lost sensor is left out, a returning one re-based."""
        events = []
        for name in self._used():
            change = self.watches[name].check(now)
            if change == 'lost':
                self._ref[name] = None
                if name == 'imu' and self.ekf is not None:
                    self.ekf.drop_anchor()
                events.append(('warn', '%s timed out: no message for %.2f s; '
                               'fusing without it' % (
                                   name, self.watches[name].timeout)))
            elif change in ('started', 'back'):
                # A returning sensor starts a new reference: its jump while
                # away (e.g. a restarted driver) is never fused.
                self._ref[name] = self._latest[name]
                if name == 'imu' and self.ekf is not None:
                    self.ekf.set_anchor()
                if change == 'back':
                    events.append(('info', '%s is back; fusing it again'
                                   % name))
        return events

    def _try_start(self, active):
        """Start at the first odometry (or, without odometry, the first IMU)."""
        if self.odom_used:
            if 'odom' not in active:
                return []
            first = self._latest['odom']
            self.ekf = PlanarEkf(first.value, first.cov)
            where = 'the first odometry pose'
        else:
            if 'imu' not in active:
                return []
            self.ekf = PlanarEkf((0.0, 0.0, 0.0), np.zeros((3, 3)))
            where = 'the origin (no odometry used)'
        for name in active:
            self._ref[name] = self._latest[name]
        self._advance_stamp(active)
        x, y, yaw = self.ekf.pose
        return [('info', 'filter started at %s: x=%.3f y=%.3f yaw=%.3f'
                 % (where, x, y, yaw))]

    def _predict(self, dt):
        """Predict with the odometry increment, or 'no motion' without it."""
        odom = self._latest['odom']
        if self.watches['odom'].active:
            increment = odom_increment(self._ref['odom'].value, odom.value)
            at_rest = max(abs(v) for v in increment) < AT_REST
            self.ekf.predict(increment, np.zeros((3, 3)) if at_rest
                             else odom.cov)
            self._ref['odom'] = odom
        else:
            self.ekf.predict((0.0, 0.0, 0.0),
                             np.diag(NO_ODOM_VARIANCE_RATE * max(dt, 1e-3)))

    def _advance_stamp(self, active):
        """Stamp the estimate with the newest fused message; note progress."""
        stamp = max(self._latest[n].stamp for n in active)
        if self.stamp is None or stamp > self.stamp:
            self.stamp = stamp
            self.updated = True


def is_finite_estimate(estimate):
    """True if ``estimate`` (``(stamp, pose, cov3)`` or None) is all finite.

    None (no estimate yet) counts as finite: there is nothing wrong to publish.
    """
    if estimate is None:
        return True
    _, pose, cov3 = estimate
    return (all(math.isfinite(v) for v in pose)
            and bool(np.all(np.isfinite(cov3))))


def _checked_cov(cov):
    """``cov`` as a floored numpy matrix; ValueError if NaN, huge or negative."""
    cov = np.array(cov, dtype=float, ndmin=2)
    if not np.all(np.isfinite(cov)):
        raise ValueError('covariance has a NaN or infinite entry')
    if np.any(np.abs(cov) > MAX_VARIANCE):
        raise ValueError('covariance has an absurd entry %g (above %g)'
                         % (np.max(np.abs(cov)), MAX_VARIANCE))
    if np.any(np.diag(cov) < 0.0):
        raise ValueError('covariance has a negative variance')
    return floored(cov)
