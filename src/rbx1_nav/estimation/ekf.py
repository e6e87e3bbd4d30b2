"""The filter maths of pose_ekf: an extended Kalman filter over the
planar pose ``(x, y, yaw)``, driven by motion increments.

* **Predict** (:meth:`PlanarEkf.predict`) with the body-frame motion
  ``(dx, dy, dyaw)`` between two odometry poses (:func:`odom_increment`),
  composed onto the estimate; the covariance grows by the increment's
  (:func:`increment_cov`: none at rest, a zero-velocity update; an
  unmeasured component grows at :data:`NO_ODOM_VARIANCE_RATE`). Without a
  motion sensor the prediction is "no motion" (:func:`no_motion_cov`).
* **Relative updates**: the change of a gyro's yaw, or of visual
  odometry's pose, since that sensor's previous update. The filter keeps a
  copy of the pose at that update (an *anchor*, a stochastic clone) in its
  state jointly with the current pose, so a change spanning several
  predict steps is fused exactly.
* **Absolute updates**: a yaw (:meth:`PlanarEkf.update_yaw`) and a
  position, with the Kalman gain (:meth:`PlanarEkf.update_position`) or
  robot_pose_ekf's per-step weight (:meth:`PlanarEkf.blend_position`).

Also the (x, y, yaw) blocks of ROS's 6x6 covariances. No rospy, no sensor
bookkeeping here (that is :mod:`rbx1_nav.estimation.sensors` and
:mod:`rbx1_nav.estimation.fusion`).
"""
import math

import numpy as np

from rbx1_nav.transform_utils import normalize_angle

__all__ = ['PlanarEkf', 'odom_increment', 'floored', 'increment_cov',
           'no_motion_cov', 'pose_covariance_3x3', 'position_covariance_2x2',
           'covariance_6x6', 'is_finite_estimate', 'MIN_VARIANCE',
           'NO_ODOM_VARIANCE_RATE', 'AT_REST']

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
    # As cov + diag(max(MIN_VARIANCE - diag, 0)), in Python floats (the
    # same doubles): a few per call, and this runs for every reading.
    for i, variance in enumerate(cov.diagonal().tolist()):
        lift = MIN_VARIANCE - variance
        if lift > 0.0:
            cov[i, i] = variance + lift
    return cov


class PlanarEkf(object):
    """EKF over ``(x, y, yaw)`` driven by motion increments.

    :meth:`predict` composes a body-frame increment onto the pose. Relative
    sensors (a gyro's yaw, visual odometry's pose) measure the change of the
    pose since their *anchor*: a copy of the pose taken at that sensor's
    previous update (:meth:`set_anchor`). Each anchor stays in the state
    (a "stochastic clone"), so the joint distribution of every anchor and the
    current pose is kept and a change spanning several predict steps is fused
    exactly. :meth:`add_rotation` appends the rotation between the IMU's
    heading reference and the output frame (the GPS frame), which each
    absolute yaw (:meth:`update_yaw`) and, as the robot moves, each fix
    (:meth:`update_position`) refine.

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

    def add_rotation(self, variance):
        """Estimate the rotation of the output frame against the reference
        of :meth:`update_yaw`'s headings, with prior ``N(0, variance)``:
        the pose's yaw is that heading plus the rotation, so the yaw's
        uncertainty grows by ``variance`` and is shared with it."""
        n = len(self.state)
        self.state_cov[2, 2] += variance
        cross = np.zeros((1, n))
        cross[0, 2] = variance
        self._append('rotation', np.zeros(1), [[variance]], cross)

    @property
    def rotation(self):
        """``(rotation, variance)`` of :meth:`add_rotation`, or None."""
        if 'rotation' not in self._blocks:
            return None
        r = self._blocks['rotation'][0]
        return (normalize_angle(self.state[r]), float(self.state_cov[r, r]))

    def update_yaw(self, yaw, variance):
        """Fuse an absolute yaw (an IMU's heading while GPS is active):
        the pose's yaw, less the rotation after :meth:`add_rotation`."""
        jac = np.zeros((1, len(self.state)))
        jac[0, 2] = 1.0
        predicted = self.state[2]
        if 'rotation' in self._blocks:
            r = self._blocks['rotation'][0]
            jac[0, r] = -1.0
            predicted = predicted - self.state[r]
        innovation = normalize_angle(yaw - predicted)
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


def no_motion_cov(dt):
    """Covariance of a step of ``dt`` seconds with no motion sensor."""
    return np.diag(NO_ODOM_VARIANCE_RATE * max(dt, 1e-3))


def increment_cov(increment, reading, dt, scale=1.0):
    """Covariance of a motion ``increment`` read from ``reading``.

    Zero at rest (wheels still: a zero-velocity update); the reading's
    covariance times ``scale`` otherwise, its unmeasured components
    replaced by the no-motion-sensor growth over ``dt``.
    """
    if max(abs(v) for v in increment) < AT_REST:
        return np.zeros((3, 3))
    cov = reading.cov * scale
    unmeasured = np.asarray(reading.unmeasured, dtype=bool)
    cov[unmeasured, unmeasured] = np.diag(no_motion_cov(dt))[unmeasured]
    return cov


def is_finite_estimate(estimate):
    """True if ``estimate`` (``(stamp, pose, cov3)`` or None) is all finite.

    None (no estimate yet) counts as finite: there is nothing wrong to publish.
    """
    if estimate is None:
        return True
    _, pose, cov3 = estimate
    return (all(math.isfinite(v) for v in pose)
            and bool(np.all(np.isfinite(cov3))))
