"""Unit tests for rbx1_nav.estimation, the planar gyro + wheel filter."""
import math

import numpy as np
import pytest
from hypothesis import given, strategies as st

from rbx1_nav.estimation.input_check import (ABSURD, DUPLICATE, NEGATIVE_VARIANCE, NOT_FINITE,
                                             OUT_OF_ORDER, ZERO_STAMP, RejectedInput)
from rbx1_nav.estimation.ekf import (PlanarEkf, covariance_6x6, floored, is_finite_estimate,
                                     odom_increment, pose_covariance_3x3)
from rbx1_nav.estimation.fusion import GyroOdomFusion
from rbx1_nav.estimation.input_check import MAX_POSITION, MAX_VARIANCE
from rbx1_nav.estimation.sensors import SensorWatch
from rbx1_nav.transform_utils import normalize_angle

ODOM_COV = np.diag([1e-4, 1e-4, 1e-2])   # wheels: poor yaw
GYRO_VAR = 1e-5                          # gyro: good yaw


def compose(pose, inc):
    x, y, yaw = pose
    c, s = math.cos(yaw), math.sin(yaw)
    return (x + c * inc[0] - s * inc[1], y + s * inc[0] + c * inc[1],
            normalize_angle(yaw + inc[2]))


# --- helpers -----------------------------------------------------------------

coord = st.floats(-50, 50)
angle = st.floats(-math.pi, math.pi)


@given(st.tuples(coord, coord, angle), st.tuples(coord, coord, angle))
def test_increment_composes_back_to_the_current_pose(prev, cur):
    got = compose(prev, odom_increment(prev, cur))
    assert got[0] == pytest.approx(cur[0], abs=1e-9)
    assert got[1] == pytest.approx(cur[1], abs=1e-9)
    assert abs(normalize_angle(got[2] - cur[2])) < 1e-9


def test_increment_is_in_the_body_frame():
    inc = odom_increment((1.0, 1.0, math.pi / 2), (1.0, 3.0, math.pi / 2))
    assert inc == pytest.approx((2.0, 0.0, 0.0), abs=1e-12)


def test_covariance_block_round_trip():
    cov3 = np.array([[1.0, 0.1, 0.2], [0.1, 2.0, 0.3], [0.2, 0.3, 3.0]])
    cov36 = covariance_6x6(cov3)
    assert len(cov36) == 36
    assert np.array_equal(pose_covariance_3x3(cov36), cov3)
    assert cov36[35] == 3.0 and cov36[5] == 0.2 and cov36[30] == 0.2


# --- PlanarEkf ---------------------------------------------------------------

def test_prediction_alone_grows_covariance_and_measurement_shrinks_it():
    ekf = PlanarEkf((0.0, 0.0, 0.0), np.diag([1e-3, 1e-3, 1e-3]))
    before = ekf.cov.copy()
    ekf.predict((0.1, 0.0, 0.05), ODOM_COV)
    predicted = ekf.cov.copy()
    assert np.all(np.diag(predicted) > np.diag(before))
    assert np.linalg.det(predicted) > np.linalg.det(before)
    ekf.update_yaw_increment(0.05, GYRO_VAR)
    assert ekf.cov[2, 2] < predicted[2, 2]
    assert np.linalg.det(ekf.cov) < np.linalg.det(predicted)
    assert np.all(np.linalg.eigvalsh(ekf.cov) > 0)


def test_gyro_update_is_the_variance_weighted_increment():
    p0 = 0.02
    ekf = PlanarEkf((0.0, 0.0, 0.3), np.diag([1e-3, 1e-3, p0]))
    var_o, var_i, d_o, d_i = 0.01, 0.0025, 0.2, 0.1
    ekf.predict((0.0, 0.0, d_o), np.diag([1e-4, 1e-4, var_o]))
    ekf.update_yaw_increment(d_i, var_i)
    fused = (d_o * var_i + d_i * var_o) / (var_o + var_i)
    assert ekf.pose[2] == pytest.approx(0.3 + fused)
    # The earlier uncertainty p0 is not "re-measured": only the step's is cut.
    assert ekf.cov[2, 2] == pytest.approx(p0 + var_o * var_i / (var_o + var_i))


def test_update_without_an_anchor_is_an_error():
    ekf = PlanarEkf((0, 0, 0), np.eye(3))
    ekf.drop_anchor()
    with pytest.raises(RuntimeError):
        ekf.update_yaw_increment(0.1, 1e-3)


def test_gyro_change_over_several_steps_is_fused_once():
    ekf = PlanarEkf((0.0, 0.0, 0.0), np.diag([1e-3, 1e-3, 1e-3]))
    for _ in range(3):  # three wheel steps of 0.1 rad, variance 0.01 each
        ekf.predict((0.1, 0.0, 0.1), np.diag([1e-4, 1e-4, 0.01]))
    ekf.update_yaw_increment(0.24, 0.01)  # one gyro reading for all three
    assert ekf.pose[2] == pytest.approx((0.3 * 0.01 + 0.24 * 0.03) / 0.04)


def test_yaw_wraps_across_pi():
    ekf = PlanarEkf((0.0, 0.0, math.pi - 0.05), np.eye(3) * 1e-3)
    ekf.predict((0.0, 0.0, 0.1), ODOM_COV)
    ekf.update_yaw_increment(0.1, GYRO_VAR)
    assert ekf.pose[2] == pytest.approx(-math.pi + 0.05)


# --- SensorWatch -------------------------------------------------------------

def test_sensor_watch_transitions():
    w = SensorWatch('imu', 1.0)
    assert w.check(0.0) is None and not w.active
    w.seen(0.5)
    assert w.check(0.6) == 'started'
    assert w.check(1.4) is None
    assert w.check(1.6) == 'lost' and not w.active
    w.seen(3.0)
    assert w.check(3.0) == 'back' and w.active


# --- GyroOdomFusion ----------------------------------------------------------

class Robot(object):
    """A scripted differential-drive robot feeding a GyroOdomFusion."""

    def __init__(self, fusion, angular_scale=1.0, rate=30.0, start=(0, 0, 0)):
        self.fusion = fusion
        self.truth = tuple(float(v) for v in start)
        self.odom = self.truth
        self.gyro_yaw = 1.0  # the gyro's own zero differs from odom's
        self.scale = angular_scale
        self.dt = 1.0 / rate
        self.t = 0.0
        self.events = []

    def run(self, seconds, v=0.0, w=0.0, odom=True, imu=True):
        for _ in range(int(round(seconds / self.dt))):
            self.t += self.dt
            inc = (v * self.dt, 0.0, w * self.dt)
            self.truth = compose(self.truth, inc)
            self.odom = compose(self.odom, (inc[0], 0.0, inc[2] * self.scale))
            self.gyro_yaw = normalize_angle(self.gyro_yaw + inc[2])
            if odom:
                self.fusion.add_odom(self.t, self.t, self.odom, ODOM_COV)
            if imu:
                self.fusion.add_imu(self.t, self.t, self.gyro_yaw, GYRO_VAR)
            self.events += self.fusion.step(self.t)

    def out_and_back(self):
        for _ in range(2):
            self.run(2.0, v=0.5)
            self.run(math.pi, w=1.0)


def yaw_error(a, b):
    return abs(normalize_angle(a - b))


def test_starts_at_the_first_odometry():
    fusion = GyroOdomFusion()
    assert fusion.step(0.0) == [] and fusion.estimate is None
    fusion.add_imu(0.05, 0.05, 0.7, GYRO_VAR)
    fusion.step(0.05)
    assert fusion.estimate is None  # no odometry yet
    fusion.add_odom(0.1, 0.1, (1.0, -2.0, 0.5), ODOM_COV)
    events = fusion.step(0.1)
    stamp, pose, cov = fusion.estimate
    assert stamp == 0.1 and pose == pytest.approx((1.0, -2.0, 0.5))
    # The output frame starts there: known, whatever odometry's covariance.
    assert np.allclose(cov, 0.0, atol=1e-8)
    assert any('started' in text for _, text in events)


def test_stationary_robot_stays_put_despite_gyro_drift():
    fusion = GyroOdomFusion()
    robot = Robot(fusion, start=(0.3, 0.4, 2.0))
    robot.run(1.0)
    cov_start = fusion.estimate[2]
    for _ in range(600):  # 20 s at rest; the gyro drifts 0.001 rad/s
        robot.gyro_yaw += 0.001 / 30.0
        robot.run(1.0 / 30.0)
    _, pose, cov = fusion.estimate
    assert pose == pytest.approx((0.3, 0.4, 2.0), abs=1e-4)  # drift: 0.02
    assert np.allclose(cov, cov_start, atol=1e-6)


def test_gyro_corrects_a_wheel_angular_scale_error():
    raw = Robot(GyroOdomFusion(imu_used=False), angular_scale=1.05)
    fused = Robot(GyroOdomFusion(), angular_scale=1.05)
    raw.out_and_back()
    fused.out_and_back()
    raw_err = yaw_error(raw.fusion.estimate[1][2], raw.truth[2])
    fused_err = yaw_error(fused.fusion.estimate[1][2], fused.truth[2])
    assert raw_err == pytest.approx(0.1 * math.pi, rel=0.02)  # 2 x 5% of pi
    assert fused_err < 0.1 * raw_err
    # The fused covariance is smaller in yaw: the gyro was fused.
    assert fused.fusion.estimate[2][2, 2] < raw.fusion.estimate[2][2, 2]


def test_odom_only_reproduces_odometry():
    robot = Robot(GyroOdomFusion(imu_used=False), angular_scale=1.05)
    robot.out_and_back()
    assert robot.fusion.estimate[1] == pytest.approx(robot.odom, abs=1e-9)


def test_imu_only_follows_the_gyro_and_keeps_position():
    robot = Robot(GyroOdomFusion(odom_used=False), angular_scale=1.05)
    robot.run(1.0)
    robot.run(2.0, v=0.2, w=0.5)
    _, (x, y, yaw), cov = robot.fusion.estimate
    assert (x, y) == (0.0, 0.0)
    assert yaw == pytest.approx(1.0, abs=1e-3)  # turned 0.5 rad/s for 2 s
    assert cov[0, 0] > 1.0  # position unknown without odometry


def test_odom_messages_are_ignored_when_not_used():
    fusion = GyroOdomFusion(odom_used=False)
    fusion.add_odom(0.0, 0.0, (5.0, 5.0, 1.0), ODOM_COV)
    fusion.step(0.0)
    assert fusion.estimate is None


def test_imu_timeout_is_dropped_and_retaken():
    robot = Robot(GyroOdomFusion(sensor_timeout=0.5), angular_scale=1.05)
    robot.run(1.0)
    cov_with_gyro = robot.fusion.estimate[2][2, 2]
    robot.run(2.0, w=0.5, imu=False)
    lost = [t for level, t in robot.events if 'imu timed out' in t]
    assert len(lost) == 1 and robot.events[-1][0] == 'warn'
    # Without the gyro the filter followed the wheels (5% too much turn)...
    wheel_turn = 1.0 * 1.05
    assert robot.fusion.estimate[1][2] == pytest.approx(wheel_turn, rel=0.05)
    # ...and its yaw variance grew by the wheels' much larger variance.
    assert robot.fusion.estimate[2][2, 2] > cov_with_gyro + 0.5 * ODOM_COV[2, 2]
    robot.gyro_yaw += 2.0  # the gyro comes back from a driver restart
    robot.run(1.0, w=0.5)
    back = [(lvl, t) for lvl, t in robot.events if 'imu is back' in t]
    assert back and back[0][0] == 'info'
    # The jump while away is not fused; the last second follows the gyro.
    assert robot.fusion.estimate[1][2] == pytest.approx(wheel_turn + 0.5,
                                                        abs=0.03)


def test_odom_timeout_is_dropped_and_retaken():
    robot = Robot(GyroOdomFusion(sensor_timeout=0.5))
    robot.run(1.0, v=0.5)
    robot.run(2.0, v=0.5, w=0.5, odom=False)
    assert any('odom timed out' in t for _, t in robot.events)
    _, (x, y, yaw), cov = robot.fusion.estimate
    assert yaw == pytest.approx(1.0, abs=0.01)  # gyro kept the heading
    assert cov[0, 0] > 1.0  # no wheels: position unknown
    robot.odom = (100.0, 100.0, 3.0)  # odometry restarts somewhere else
    robot.run(1.0, v=0.5)
    assert any('odom is back' in t for _, t in robot.events)
    _, (x2, y2, _), _ = robot.fusion.estimate
    assert math.hypot(x2 - x, y2 - y) == pytest.approx(0.5, abs=0.05)


def test_no_sensor_no_update():
    robot = Robot(GyroOdomFusion(sensor_timeout=0.5))
    robot.run(1.0)
    robot.run(0.3, odom=False, imu=False)
    assert not robot.fusion.updated  # nothing new: nothing to publish
    stamp = robot.fusion.estimate[0]
    robot.run(2.0, odom=False, imu=False)
    assert robot.fusion.estimate[0] == stamp


@pytest.mark.parametrize('bad', [float('nan'), float('inf')])
def test_non_finite_input_is_rejected(bad):
    fusion = GyroOdomFusion()
    with pytest.raises(ValueError):
        fusion.add_odom(0.0, 0.0, (bad, 0.0, 0.0), ODOM_COV)
    with pytest.raises(ValueError):
        fusion.add_odom(0.0, 0.0, (0.0, 0.0, 0.0), np.diag([bad, 1, 1]))
    with pytest.raises(ValueError):
        fusion.add_imu(0.0, 0.0, bad, GYRO_VAR)
    with pytest.raises(ValueError):
        fusion.add_imu(0.0, 0.0, 0.0, -1.0)
    fusion.step(0.0)
    assert fusion.estimate is None


def test_needs_at_least_one_sensor():
    with pytest.raises(ValueError):
        GyroOdomFusion(odom_used=False, imu_used=False)


# --- absurd but finite input -------------------------------------------------

@pytest.mark.parametrize('huge', [1e308, MAX_VARIANCE * 10, -1e308])
def test_absurd_covariances_are_rejected(huge):
    # A huge variance means "not measured" (test_pose_ekf_unmeasured.py);
    # a huge covariance between two measured components is absurd.
    fusion = GyroOdomFusion()
    cov = ODOM_COV.copy()
    cov[0, 1] = cov[1, 0] = huge
    with pytest.raises(ValueError, match='absurd'):
        fusion.add_odom(1.0, 1.0, (0.0, 0.0, 0.0), cov)
    fusion.step(1.0)
    assert fusion.estimate is None


def test_variances_at_the_cap_are_accepted_and_stay_finite():
    fusion = GyroOdomFusion()
    odom, events = (0.0, 0.0, 0.0), []
    for k in range(1, 3001):  # 100 s at 30 Hz, driving in circles
        t = k / 30.0
        odom = compose(odom, (0.02, 0.0, 0.02))
        fusion.add_odom(t, t, odom, np.full((3, 3), MAX_VARIANCE))
        fusion.add_imu(t, t, odom[2], MAX_VARIANCE)
        events += fusion.step(t)
        assert is_finite_estimate(fusion.estimate)
    assert fusion.estimate[1] == pytest.approx(odom, abs=1e-6)
    assert not any('restarted' in text for _, text in events)


@pytest.mark.parametrize('x', [1e308, -1e308, MAX_POSITION * 1.01])
def test_absurd_positions_are_rejected(x):
    fusion = GyroOdomFusion()
    with pytest.raises(ValueError, match='absurd'):
        fusion.add_odom(0.0, 0.0, (x, 0.0, 0.0), ODOM_COV)
    with pytest.raises(ValueError, match='absurd'):
        fusion.add_odom(0.0, 0.0, (0.0, x, 0.0), ODOM_COV)


def test_odometry_jumping_across_the_float_range_never_gives_nan():
    fusion = GyroOdomFusion()
    for k, x in enumerate((0.0, -1e308, 1e308, 1.0)):
        t = 0.1 * (k + 1)
        try:
            fusion.add_odom(t, t, (x, 0.0, 0.0), ODOM_COV)
        except ValueError:
            pass
        fusion.add_imu(t, t, 0.0, GYRO_VAR)
        fusion.step(t)
        assert is_finite_estimate(fusion.estimate)
    assert fusion.estimate[1] == pytest.approx((1.0, 0.0, 0.0))


def test_increment_that_overflows_is_an_error():
    with pytest.raises(ValueError, match='not finite'):
        odom_increment((-1e308, 0.0, 0.0), (1e308, 0.0, 0.0))
    with pytest.raises(ValueError, match='not finite'):
        odom_increment((0.0, 0.0, -1e308), (0.0, 0.0, 1e308))


def test_floored_does_not_overflow_near_the_float_limit():
    cov = floored(np.diag([1.7e308, 1.0, 1.0]))
    assert np.all(np.isfinite(cov)) and cov[0, 0] == 1.7e308


def test_a_filter_that_blows_up_restarts_from_the_next_odometry():
    robot = Robot(GyroOdomFusion())
    robot.run(1.0, v=0.5)
    robot.fusion.ekf.cov[0, 0] = float('inf')  # however it got there
    robot.run(1.0 / 30.0, v=0.5)
    restarts = [(lvl, t) for lvl, t in robot.events if 'restarted' in t]
    assert restarts == [('warn', 'filter restarted: the estimate is no longer '
                         'finite; it starts again from the next odometry message')]
    assert robot.fusion.estimate is None and not robot.fusion.updated
    robot.run(1.0 / 30.0, v=0.5)  # the next odometry restarts it there
    _, pose, cov = robot.fusion.estimate
    assert pose == pytest.approx(robot.odom) and np.allclose(cov, 0.0,
                                                             atol=1e-8)
    robot.run(1.0, v=0.5)
    assert robot.fusion.estimate[1] == pytest.approx(robot.odom, abs=1e-3)
    assert is_finite_estimate(robot.fusion.estimate)


def test_a_nan_yaw_in_the_filter_restarts_it_instead_of_raising():
    robot = Robot(GyroOdomFusion())
    robot.run(1.0, w=0.5)
    robot.fusion.ekf.mean[2] = float('nan')
    robot.run(1.0 / 30.0, w=0.5)
    assert any('restarted' in t for _, t in robot.events)
    assert robot.fusion.estimate is None


def test_is_finite_estimate():
    assert is_finite_estimate(None)
    assert is_finite_estimate((0.0, (1.0, 2.0, 3.0), np.eye(3)))
    assert not is_finite_estimate((0.0, (1.0, float('nan'), 3.0), np.eye(3)))
    assert not is_finite_estimate((0.0, (1.0, 2.0, 3.0), np.full((3, 3), np.inf)))


# --- out-of-order and bad readings, ROS time moving backwards ----------------

def test_odometry_half_a_second_late_is_dropped_and_the_pose_never_moves_back():
    # The run: 41 odometry messages 0.5 s late in 6 s, each
    # arriving after the current one and before the gyro's; each moved the
    # published pose back 47 mm (0.5 s at 0.1 m/s) before this check.
    fusion = GyroOdomFusion()
    sent, published, warnings = [], [], []
    t, x = 0.0, 0.0
    for k in range(180):  # 6 s at 30 Hz, driving straight at 0.1 m/s
        t, x = t + 1.0 / 30.0, x + 0.1 / 30.0
        sent.append((t, (x, 0.0, 0.0)))
        fusion.add_odom(t, t, (x, 0.0, 0.0), ODOM_COV)
        if k >= 16 and k % 4 == 0:  # the message of 15 steps (0.5 s) ago
            stamp, pose = sent[-16]
            with pytest.raises(RejectedInput) as caught:
                fusion.add_odom(t, stamp, pose, ODOM_COV)
            assert caught.value.kind == OUT_OF_ORDER
            warnings.append(fusion.inputs.warning(caught.value, t,
                                                  'odom on /odom'))
        fusion.add_imu(t, t, 1.0, GYRO_VAR)
        fusion.step(t)
        if fusion.updated:
            published.append(fusion.estimate[:2])
    assert len(warnings) == 41 and len(published) == 180
    stamps = [stamp for stamp, _ in published]
    assert all(b > a for a, b in zip(stamps, stamps[1:]))
    assert [pose[0] for _, pose in published] == pytest.approx(
        [pose[0] for _, pose in sent], abs=1e-9)
    # One warning in these 6 s (one per 10 s), naming the delay; the
    # other 40 drops are counted for the next one.
    said = [w for w in warnings if w]
    assert len(said) == 1 and 'out of order' in said[0]
    assert 'is 0.500 s older than the newest reading taken' in said[0]
    assert fusion.inputs.dropped('odom', OUT_OF_ORDER) == 40


def feed(fusion, sensor, stamp, number=1.0, variance=1e-4):
    """One reading of ``sensor``: ``number`` is its x (the IMU's yaw)."""
    if sensor == 'imu':
        fusion.add_imu(stamp, stamp, number, variance)
    elif sensor == 'gps':
        fusion.add_gps(stamp, stamp, (number, 2.0), np.eye(2) * variance)
    else:
        getattr(fusion, 'add_' + sensor)(stamp, stamp, (number, 2.0, 0.5),
                                         np.eye(3) * variance)


BAD_READINGS = [  # stamp, x (the IMU's yaw), variance, kind
    (0.0, 1.0, 1e-4, ZERO_STAMP), (5.0, 1.0, 1e-4, DUPLICATE),
    (4.5, 1.0, 1e-4, OUT_OF_ORDER), (6.0, float('nan'), 1e-4, NOT_FINITE),
    (6.0, 1.0, -1e-4, NEGATIVE_VARIANCE), (6.0, 1e300, 1e-4, ABSURD)]


@pytest.mark.parametrize('sensor,stamp,number,variance,kind', [
    (sensor,) + bad for sensor in ('odom', 'imu', 'vo', 'gps')
    for bad in BAD_READINGS
    # A yaw has no absurd value: any finite angle wraps.
    if not (sensor == 'imu' and bad[1] == 1e300)])
def test_each_sensor_drops_each_kind_of_bad_reading(sensor, stamp, number,
                                                    variance, kind):
    fusion = GyroOdomFusion(vo_used=True, gps_used=True)
    feed(fusion, sensor, 5.0)
    with pytest.raises(RejectedInput) as caught:
        feed(fusion, sensor, stamp, number, variance)
    assert (caught.value.sensor, caught.value.kind) == (sensor, kind)
    assert fusion.inputs.newest(sensor) == 5.0
    assert fusion.watches[sensor].last_stamp == 5.0  # nothing kept
    feed(fusion, sensor, 6.0)
    assert fusion.watches[sensor].last_stamp == 6.0


def test_time_moving_back_restarts_from_the_next_readings_at_once():
    fusion = GyroOdomFusion()
    robot = Robot(fusion)
    robot.run(20.0, v=0.2)
    assert fusion.check_clock(robot.t) == 0.0
    robot.t -= 10.0  # the simulator restarts 10 s back
    assert fusion.check_clock(robot.t) == pytest.approx(10.0)
    assert fusion.estimate is None
    robot.run(1.0 / 30.0, v=0.2)  # the new clock's first readings
    assert fusion.updated
    stamp, pose, _ = fusion.estimate
    assert stamp == pytest.approx(robot.t) and stamp < 11.0
    assert pose == pytest.approx(robot.odom)
    robot.run(1.0, v=0.2)
    assert fusion.estimate[0] == pytest.approx(robot.t)
    assert fusion.estimate[1] == pytest.approx(robot.odom, abs=1e-6)
    assert fusion.restarts == 1


def test_a_restart_on_the_same_clock_never_publishes_an_older_stamp():
    fusion = GyroOdomFusion()
    fusion.add_odom(1.0, 1.0, (0.0, 0.0, 0.0), ODOM_COV)
    fusion.add_imu(1.02, 1.02, 0.0, GYRO_VAR)
    fusion.step(1.02)
    assert fusion.estimate[0] == 1.02  # the gyro's newer stamp
    fusion.restart()  # e.g. the estimate stopped being finite
    with pytest.raises(RejectedInput):
        fusion.add_odom(1.03, 1.0, (0.0, 0.0, 0.0), ODOM_COV)
    fusion.add_odom(1.03, 1.01, (0.01, 0.0, 0.0), ODOM_COV)
    fusion.step(1.03)
    assert fusion.estimate is not None and not fusion.updated  # 1.01: old
    fusion.add_odom(1.04, 1.04, (0.02, 0.0, 0.0), ODOM_COV)
    fusion.step(1.04)
    assert fusion.updated and fusion.estimate[0] == 1.04
