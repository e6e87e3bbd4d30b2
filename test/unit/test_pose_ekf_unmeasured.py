"""pose_ekf and the "do not use this component" variances drivers publish
(1e6, 1e10, 1e308, DBL_MAX, -1, inf): the component is left unmeasured,
said once, and the published covariance stays that of what was measured
(rbx1_nav.estimation)."""
import math
import sys

import numpy as np
import pytest

from rbx1_nav.estimation.fusion import GyroOdomFusion

GYRO_VAR = 1e-6
ODOM_XY_VAR = 1e-3
CONVENTIONS = [1e6, 1e10, 1e308, sys.float_info.max, -1.0, float('inf')]


def arc(fusion, odom_yaw_var, seconds=20.0, rate=30.0):
    """An arc (0.3 m/s, 0.2 rad/s) fed straight into ``fusion``: odometry
    with x, y variance 1e-3 and yaw variance ``odom_yaw_var``, a gyro with
    variance 1e-6 whose heading starts at 0.4 rad. Returns the events and
    the true final pose."""
    pose, events = [0.0, 0.0, 0.0], []
    cov = np.diag([ODOM_XY_VAR, ODOM_XY_VAR, odom_yaw_var])
    dt = 1.0 / rate
    for k in range(1, int(seconds * rate) + 1):
        t = k * dt
        pose[0] += 0.3 * dt * math.cos(pose[2])
        pose[1] += 0.3 * dt * math.sin(pose[2])
        pose[2] += 0.2 * dt
        fusion.add_odom(t, t, tuple(pose), cov)
        fusion.add_imu(t, t, 0.4 + pose[2], GYRO_VAR)
        events += fusion.step(t)
    return events, pose


@pytest.mark.parametrize('variance', CONVENTIONS)
def test_odometry_yaw_not_measured_gives_a_bounded_honest_covariance(
        variance):
    fusion = GyroOdomFusion(topics={'odom': '/encoder'})
    events, truth = arc(fusion, variance)
    _, pose, cov = fusion.estimate
    assert pose == pytest.approx((truth[0], truth[1],
                                  math.remainder(truth[2], 2 * math.pi)),
                                 abs=1e-6)
    steps = 20 * 30
    # Yaw: the gyro's accumulated noise (one relative reading a step).
    assert cov[2, 2] == pytest.approx(steps * GYRO_VAR, rel=0.05)
    # x, y: odometry's accumulated variance, plus what the heading's
    # uncertainty adds over the 6 m arc: the same order, nowhere near 1e6.
    for i in (0, 1):
        assert steps * ODOM_XY_VAR * 0.3 < cov[i, i] < steps * ODOM_XY_VAR * 3
    assert np.all(np.isfinite(cov))
    notes = [t for lvl, t in events if 'not measured' in t]
    assert len(notes) == 1 and all(lvl == 'info' for lvl, t in events
                                   if 'not measured' in t)
    assert notes[0].startswith('odom on /encoder: variance ')
    assert 'of yaw means "not measured"' in notes[0]


def test_the_same_with_a_sane_yaw_variance_for_comparison():
    """With the yaw measured (a poor 1e-2), the estimate is the same arc."""
    fusion = GyroOdomFusion()
    _, truth = arc(fusion, 1e-2)
    assert fusion.estimate[1][:2] == pytest.approx(truth[:2], abs=1e-6)


@pytest.mark.parametrize('variance', CONVENTIONS)
def test_an_imu_without_yaw_fuses_nothing(variance):
    fusion = GyroOdomFusion()
    for k in range(1, 31):
        t = k / 30.0
        fusion.add_odom(t, t, (0.1 * k, 0.0, 0.0), np.eye(3) * 1e-3)
        fusion.add_imu(t, t, 0.05 * k, variance)  # would turn the robot
        fusion.step(t)
    assert fusion.estimate[1] == pytest.approx((3.0, 0.0, 0.0), abs=1e-9)


@pytest.mark.parametrize('variance', CONVENTIONS)
def test_a_gps_axis_not_measured_is_not_fused(variance):
    fusion = GyroOdomFusion(gps_used=True, gps_kalman=True)
    for k in range(1, 151):
        t = k / 30.0
        fusion.add_odom(t, t, (0.0, 0.0, 0.0), np.eye(3) * 1e-3)
        fusion.add_imu(t, t, 0.0, GYRO_VAR)
        if k == 10:
            fusion.add_gps(t, t, (0.0, 0.0), np.diag([0.1, 0.1]))
        elif k % 10 == 0:  # y claims 7 m, but says it is not measured
            fusion.add_gps(t, t, (2.0, 7.0), np.diag([0.1, variance]))
        fusion.step(t)
    _, (x, y, _), cov = fusion.estimate
    assert x == pytest.approx(2.0, abs=0.2) and y == pytest.approx(0.0)
    assert np.all(np.isfinite(cov)) and cov[1, 1] <= 0.1 + 1e-6


def test_a_gps_without_y_cannot_start_the_filter():
    fusion = GyroOdomFusion(gps_used=True)
    fusion.add_imu(1.0, 1.0, 0.0, GYRO_VAR)
    fusion.add_gps(1.0, 1.0, (2.0, 7.0), np.diag([0.1, 1e10]))
    fusion.step(1.0)
    assert fusion.estimate is None
