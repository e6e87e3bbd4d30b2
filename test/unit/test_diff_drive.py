"""Unit tests for rbx1_nav.sim.diff_drive, the fake TurtleBot's model (no master)."""
import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from rbx1_nav.common.geometry import arc_step
from rbx1_nav.common.params import number
from rbx1_nav.sim.diff_drive import (DiffDriveConfig, DiffDriveFleet, DiffDriveSim,
                                     arc_steps, covariance_from_diagonal)
from rbx1_nav.sim.params import DIFF_DRIVE_PARAMS
from rbx1_nav.transform_utils import Pose2D, quat_to_angle, yaw_to_quaternion

RATE = 50.0
#: (minimum, maximum) of each numeric setting, as declared.
LIMITS = {spec.name: (spec.options['minimum'], spec.options['maximum'])
          for spec in DIFF_DRIVE_PARAMS if spec.check is number}


def drive(sim, v, w, duration, start=0.0, rate=RATE):
    """Step ``sim`` at ``rate`` from ``start`` for ``duration`` s, sending the
    command before every step (like a teleop node). Returns the end time."""
    n = int(round(duration * rate))
    sim.step(start)
    for k in range(1, n + 1):
        sim.command(v, w, start + (k - 1) / rate)
        sim.step(start + k / rate)
    return start + n / rate


def ideal(**overrides):
    return DiffDriveSim(DiffDriveConfig(**overrides))


# --- arc_step: the exact integrator -------------------------------------------

def test_straight_line():
    p = arc_step(Pose2D(1.0, 2.0, math.pi / 2), 0.4, 0.0)
    assert (p.x, p.y, p.yaw) == pytest.approx((1.0, 2.4, math.pi / 2), abs=1e-12)


def test_quarter_arc_ends_where_geometry_says():
    radius = 0.4
    p = arc_step(Pose2D(), radius * math.pi / 2, math.pi / 2)
    assert (p.x, p.y, p.yaw) == pytest.approx((radius, radius, math.pi / 2), abs=1e-9)
    p = arc_step(Pose2D(), radius * math.pi / 2, -math.pi / 2)  # turning right
    assert (p.x, p.y, p.yaw) == pytest.approx((radius, -radius, -math.pi / 2), abs=1e-9)


def test_turning_in_place_does_not_translate():
    p = arc_step(Pose2D(0.3, -0.2, 0.1), 0.0, 2.5)
    assert (p.x, p.y, p.yaw) == pytest.approx((0.3, -0.2, 2.6), abs=1e-12)


steps = st.floats(-5.0, 5.0, allow_nan=False)


@given(st.floats(-math.pi, math.pi), steps, steps)
def test_arc_matches_circle_geometry(theta, ds, dtheta):
    """End point on the circle of radius ds/dtheta about the turn centre."""
    p = arc_step(Pose2D(0.0, 0.0, theta), ds, dtheta)
    if abs(dtheta) > 1e-3:
        r = ds / dtheta
        expected = (r * (math.sin(theta + dtheta) - math.sin(theta)),
                    -r * (math.cos(theta + dtheta) - math.cos(theta)))
    else:  # a near-straight line: compare with many short Euler steps
        n, x, y, th = 10000, 0.0, 0.0, theta
        for _ in range(n):
            x += ds / n * math.cos(th + 0.5 * dtheta / n)
            y += ds / n * math.sin(th + 0.5 * dtheta / n)
            th += dtheta / n
        expected = (x, y)
    assert (p.x, p.y) == pytest.approx(expected, abs=1e-9)
    assert math.cos(p.yaw) == pytest.approx(math.cos(theta + dtheta), abs=1e-9)
    assert math.sin(p.yaw) == pytest.approx(math.sin(theta + dtheta), abs=1e-9)


@given(st.floats(-math.pi, math.pi), steps, steps)
def test_the_simulators_array_form_matches_the_controllers_arc(theta, ds, dtheta):
    """sim.diff_drive.arc_steps (numpy, N robots) is common.geometry.arc_step."""
    one = arc_step(Pose2D(0.1, -0.2, theta), ds, dtheta)
    row = arc_steps(np.array([[0.1, -0.2, theta]]), np.array([ds]), np.array([dtheta]))[0]
    assert tuple(row) == pytest.approx((one.x, one.y, one.yaw), abs=1e-12)


@given(st.floats(-math.pi, math.pi), steps, steps)
def test_two_half_steps_equal_one_step(theta, ds, dtheta):
    """Exactness for constant (v, w): step size does not change the result."""
    one = arc_step(Pose2D(0.0, 0.0, theta), ds, dtheta)
    two = arc_step(arc_step(Pose2D(0.0, 0.0, theta), ds / 2, dtheta / 2), ds / 2, dtheta / 2)
    assert (two.x, two.y) == pytest.approx((one.x, one.y), abs=1e-9)


# --- the simulated base --------------------------------------------------------

def test_two_seconds_at_0_2_m_per_s_is_0_4_m():
    sim = ideal()
    drive(sim, 0.2, 0.0, 2.0)
    assert (sim.truth.x, sim.truth.y, sim.truth.yaw) == pytest.approx((0.4, 0, 0), abs=1e-9)
    assert (sim.odom.x, sim.odom.y) == pytest.approx((0.4, 0.0), abs=1e-9)


def test_full_circle_returns_to_start():
    sim = ideal()
    w = 0.5
    drive(sim, 0.2, w, 2 * math.pi / w, rate=1.0 / (2 * math.pi / w / 629))
    assert math.hypot(sim.truth.x, sim.truth.y) < 1e-3
    assert math.hypot(sim.truth.x, sim.truth.y) < 1e-9  # it is in fact exact
    assert abs(math.remainder(sim.truth.yaw, 2 * math.pi)) < 1e-9


def test_first_step_only_sets_the_clock():
    sim = ideal()
    sim.command(0.2, 0.0, 100.0)
    assert sim.step(100.0) is False
    assert sim.step(100.02) is True
    assert sim.truth.x == pytest.approx(0.004, abs=1e-12)


def test_watchdog_stops_within_timeout_plus_one_period():
    sim = ideal(cmd_timeout=0.5)
    sim.step(0.0)
    sim.command(0.2, 0.0, 0.0)
    last_moving = None
    for k in range(1, 101):
        sim.step(k / RATE)
        if sim.velocity[0] != 0.0:
            last_moving = k / RATE
    assert sim.velocity == (0.0, 0.0) and sim.timed_out
    assert 0.5 - 1 / RATE <= last_moving <= 0.5 + 1 / RATE
    assert sim.truth.x == pytest.approx(0.1, abs=0.2 / RATE)


def test_command_time_is_when_the_command_it_runs_became_due():
    sim = ideal(cmd_timeout=0.5, command_latency=0.03)
    sim.step(0.0)
    assert sim.command_time is None  # no command yet
    sim.command(0.2, 0.0, 0.25)
    sim.step(0.26)
    assert sim.command_time is None  # not due before 0.28
    sim.step(0.3)
    assert sim.command_time == pytest.approx(0.28, abs=1e-12)
    sim.step(1.0)  # the watchdog stopped it; the time stays the command's
    assert sim.timed_out and sim.command_time == pytest.approx(0.28, abs=1e-12)


def test_no_command_ever_means_standing_still():
    sim = ideal()
    for k in range(50):
        sim.step(k / RATE)
    assert (sim.truth.x, sim.truth.y, sim.velocity) == (0.0, 0.0, (0.0, 0.0))


@pytest.mark.parametrize('v, w', [(float('nan'), 0.0), (0.1, float('inf')),
                                  (-float('inf'), float('nan'))])
def test_non_finite_command_is_rejected_as_stop(v, w):
    sim = ideal()
    drive(sim, 0.2, 0.3, 0.2)
    assert sim.command(v, w, 0.2) == 'non-finite'
    sim.step(0.22)
    assert sim.velocity == (0.0, 0.0)
    assert all(math.isfinite(c) for c in (sim.truth.x, sim.truth.y, sim.truth.yaw))


def test_absurd_speeds_are_clamped():
    sim = ideal(max_linear_speed=0.5, max_angular_speed=2.0)
    assert sim.command(1e9, -1e9, 0.0) == 'clamped'
    assert sim.command(0.1, 0.2, 0.0) is None
    sim = ideal(max_linear_speed=0.5, max_angular_speed=2.0)
    drive(sim, 1e9, -1e9, 1.0)
    assert sim.velocity == (0.5, -2.0)


def replay(sim, commands):
    """Send each (v, w, dt) at the current time and step dt on; yield per step."""
    t = 0.0
    sim.step(t)
    for v, w, dt in commands:
        sim.command(v, w, t)
        t += dt
        sim.step(t)
        yield t


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.floats(), st.floats(), st.floats(1e-4, 10.0)),
                min_size=1, max_size=30))
def test_any_input_leaves_the_pose_finite(commands):
    cfg = DiffDriveConfig(accel_limit_linear=1.0, encoder_noise=0.01,
                          gyro_noise_density=0.01, seed=0)
    sim = DiffDriveSim(cfg)
    for _ in replay(sim, commands):
        for value in (sim.truth.x, sim.truth.y, sim.truth.yaw, sim.odom.x,
                      sim.odom.y, sim.odom.yaw, sim.gyro_yaw, *sim.wheel_angles):
            assert math.isfinite(value)
        assert abs(sim.velocity[0]) <= cfg.max_linear_speed
        assert abs(sim.velocity[1]) <= cfg.max_angular_speed


def test_time_moving_backwards_rebases_without_motion():
    sim = ideal()
    drive(sim, 0.2, 0.0, 1.0)
    x = sim.truth.x
    assert sim.step(0.5) is False
    assert sim.truth.x == x
    sim.command(0.2, 0.0, 0.5)
    sim.step(0.52)
    assert sim.truth.x == pytest.approx(x + 0.004, abs=1e-12)


def test_acceleration_limits_ramp_the_speed():
    sim = ideal(accel_limit_linear=1.0, accel_limit_angular=2.0)
    sim.step(0.0)
    sim.command(0.2, 1.0, 0.0)
    speeds = []
    for k in range(1, 31):
        sim.command(0.2, 1.0, (k - 1) / RATE)
        sim.step(k / RATE)
        speeds.append(sim.velocity)
    assert speeds[0] == pytest.approx((0.02, 0.04))
    assert speeds[9] == pytest.approx((0.2, 0.4))    # 0.2 m/s after 0.2 s
    assert speeds[29] == pytest.approx((0.2, 1.0))   # 1 rad/s after 0.5 s
    assert all(np.diff([v for v, _ in speeds]) <= 1.0 / RATE + 1e-12)


def test_command_latency_delays_execution():
    sim = ideal(command_latency=0.1)
    sim.step(0.0)
    sim.command(0.2, 0.0, 0.0)
    sim.step(0.08)
    assert sim.velocity == (0.0, 0.0)
    sim.step(0.1)
    assert sim.velocity == (0.2, 0.0)


# --- odometry, wheels and gyro ----------------------------------------------------

def test_joint_angles_match_distance_travelled():
    sim = ideal(wheel_radius=0.033)
    drive(sim, 0.2, 0.0, 2.0)
    left, right = sim.wheel_angles
    assert left == pytest.approx(0.4 / 0.033, abs=1e-9)
    assert right == pytest.approx(0.4 / 0.033, abs=1e-9)
    assert sim.wheel_velocities == pytest.approx([0.2 / 0.033] * 2)
    sim = ideal(wheel_radius=0.033, wheel_separation=0.26)
    drive(sim, 0.0, 1.0, 1.0)
    assert sim.wheel_angles == pytest.approx([-0.13 / 0.033, 0.13 / 0.033], abs=1e-9)


def test_scale_errors_distort_odometry_not_truth():
    sim = ideal(linear_scale_error=1.1, angular_scale_error=1.2)
    drive(sim, 0.2, 0.0, 2.0)
    assert sim.truth.x == pytest.approx(0.4, abs=1e-9)
    assert sim.odom.x == pytest.approx(1.1 * 0.4, abs=1e-9)
    drive(sim, 0.0, 0.5, 1.0, start=2.0)
    assert sim.truth.yaw == pytest.approx(0.5, abs=1e-9)
    assert sim.odom.yaw == pytest.approx(1.2 * 0.5, abs=1e-9)
    assert sim.odom_velocity == pytest.approx((0.0, 1.2 * 0.5))


def test_scale_corrections_cancel_the_errors():
    sim = ideal(linear_scale_error=1.1, angular_scale_error=1.2,
                odom_linear_scale_correction=1 / 1.1,
                odom_angular_scale_correction=1 / 1.2)
    drive(sim, 0.2, 0.4, 3.0)
    assert (sim.odom.x, sim.odom.y, sim.odom.yaw) == pytest.approx(
        (sim.truth.x, sim.truth.y, sim.truth.yaw), abs=1e-9)


def test_a_larger_right_wheel_makes_odometry_see_a_straight_path_curve_right():
    sim = ideal(right_wheel_radius_error=1.005, wheel_separation=0.26)
    drive(sim, 0.2, 0.0, 5.0)
    assert (sim.truth.x, sim.truth.y, sim.truth.yaw) == pytest.approx(
        (1.0, 0.0, 0.0), abs=1e-9)
    # The right encoder reads 1 m / 1.005 of travel, the left 1 m.
    right = 1.0 / 1.005
    assert sim.odom.yaw == pytest.approx((right - 1.0) / 0.26, abs=1e-9)
    assert sim.odom.yaw < 0
    assert sim.wheel_angles[1] == pytest.approx(right / 0.033, abs=1e-9)


def test_diff_drive_controller_multipliers_cancel_radius_and_separation_errors():
    ed, eb = 1.005, 1.02  # right/left diameter ratio, separation error
    sim = ideal(right_wheel_radius_error=ed, angular_scale_error=eb,
                left_wheel_radius_multiplier=2.0 / (ed + 1.0),
                right_wheel_radius_multiplier=2.0 / (1.0 / ed + 1.0),
                wheel_separation_multiplier=eb)
    # Both wheels now read 2 / (1 + ed) of their travel: a scale, no curve.
    scale = 2.0 / (ed + 1.0)
    drive(sim, 0.2, 0.0, 3.0)
    assert (sim.odom.x, sim.odom.y, sim.odom.yaw) == pytest.approx(
        (scale * sim.truth.x, 0.0, 0.0), abs=1e-9)
    drive(sim, 0.0, 0.4, 3.0, start=3.0)
    assert sim.odom.yaw == pytest.approx(scale * sim.truth.yaw, abs=1e-9)


def test_gyro_follows_true_yaw_rate_despite_odometry_errors():
    sim = ideal(angular_scale_error=1.05, gyro_bias=0.01)
    drive(sim, 0.0, 0.5, 1.0)
    assert sim.gyro_rate == pytest.approx(0.5 + 0.01, abs=1e-12)
    assert sim.gyro_yaw == pytest.approx(0.5 + 0.01, abs=1e-9)
    assert sim.odom.yaw == pytest.approx(0.525, abs=1e-9)


def test_gyro_variances_are_never_zero():
    yaw_var, rate_var = ideal().gyro_variances(0.02)
    assert yaw_var > 0 and rate_var > 0
    yaw_var, rate_var = ideal(gyro_noise_density=0.01).gyro_variances(0.02)
    assert rate_var == pytest.approx(0.01 ** 2 / 0.02)


def noisy_run(seed, rate, **config):
    sim = DiffDriveSim(DiffDriveConfig(seed=seed, **config))
    drive(sim, 0.5, 0.0, 2.0, rate=rate)
    return sim


def test_seed_makes_noise_reproducible():
    noise = dict(encoder_noise=0.01, gyro_noise_density=0.01)
    a, b, c = (noisy_run(seed, RATE, **noise) for seed in (7, 7, 8))
    assert (a.odom, a.gyro_yaw, a.wheel_angles) == (b.odom, b.gyro_yaw, b.wheel_angles)
    assert a.odom != c.odom
    assert a.odom != a.truth


def test_noise_grows_with_distance_not_with_step_rate():
    """Error spread over 1 m is about the same stepping at 10 Hz or 100 Hz
    (300 robots of one fleet, each with noise of its own)."""
    noise = DiffDriveConfig(encoder_noise=0.01, gyro_noise_density=0.01, seed=3)
    for rate in (10.0, 100.0):
        fleet = DiffDriveFleet(300, noise)
        fleet.step(0.0)
        for k in range(1, int(round(2.0 * rate)) + 1):
            for robot in range(fleet.size):
                fleet.command(robot, 0.5, 0.0, (k - 1) / rate)
            fleet.step(k / rate)
        # Theory: x error sigma = 0.01 * sqrt(1 m) / sqrt(2); yaw sigma = 0.01 * sqrt(2 s).
        x_sd = np.std(fleet.odom[:, 0] - fleet.truth[:, 0])
        assert x_sd == pytest.approx(0.01 / math.sqrt(2), rel=0.2), rate
        assert np.std(fleet.gyro_yaw) == pytest.approx(0.01 * math.sqrt(2), rel=0.2), rate


# --- helpers and configuration --------------------------------------------------

@given(st.floats(-math.pi, math.pi))
def test_yaw_to_quaternion_round_trips(yaw):
    q = yaw_to_quaternion(yaw)
    assert sum(c * c for c in q) == pytest.approx(1.0)
    assert abs(math.remainder(quat_to_angle(q) - yaw, 2 * math.pi)) < 1e-9


def test_covariance_from_diagonal():
    cov = covariance_from_diagonal([1, 2, 3, 4, 5, 6])
    assert len(cov) == 36
    assert [cov[7 * i] for i in range(6)] == [1, 2, 3, 4, 5, 6]
    assert sum(cov) == 21


@pytest.mark.parametrize('bad', [[1, 1, 1, 1, 1, 0], [1] * 5, [1, 1, 1, 1, 1, -1],
                                 [1, 1, 1, 1, 1, float('nan')]])
def test_covariance_rejects_unusable_diagonals(bad):
    with pytest.raises(ValueError, match='six finite positive'):
        covariance_from_diagonal(bad)


@pytest.mark.parametrize('field, value', [('wheel_separation', 0.0), ('wheel_radius', -1),
                                          ('cmd_timeout', float('nan')),
                                          ('accel_limit_linear', -1.0),
                                          ('max_linear_speed', 'fast'), ('seed', 1.5)])
def test_invalid_config_is_rejected_with_its_name(field, value):
    with pytest.raises(ValueError, match=field):
        DiffDriveSim(DiffDriveConfig(**{field: value}))


def test_defaults_are_valid_and_named():
    assert DiffDriveConfig().problems() == []
    assert 'cmd_timeout' in DiffDriveConfig.names()
    assert DiffDriveConfig().wheel_separation == 0.26


@pytest.mark.parametrize('field, value', [('wheel_separation', 1e308), ('wheel_radius', 1e-300),
                                          ('linear_scale_error', 1e308),
                                          ('gyro_noise_density', 1e300),
                                          ('seed', -1), ('seed', True), ('cmd_timeout', True)])
def test_absurd_config_is_rejected_with_its_name(field, value):
    assert any(field in p for p in DiffDriveConfig(**{field: value}).problems())
    with pytest.raises(ValueError, match=field):
        DiffDriveSim(DiffDriveConfig(**{field: value}))


def test_config_from_params_parses_strings_and_names_every_bad_value():
    cfg = DiffDriveConfig.from_params({'cmd_timeout': '1e3', 'wheel_radius': 0.05,
                                       'seed': '7'}, prefix='~')
    assert (cfg.cmd_timeout, cfg.wheel_radius, cfg.seed) == (1000.0, 0.05, 7)
    assert cfg.problems() == []
    assert DiffDriveConfig.from_params({'seed': None}).seed is None
    with pytest.raises(ValueError, match='~publish_imu is not a fake robot'):
        DiffDriveConfig.from_params({'publish_imu': True}, prefix='~')
    with pytest.raises(ValueError) as err:
        DiffDriveConfig.from_params({'cmd_timeout': float('inf'), 'wheel_radius': 0,
                                     'gyro_bias': 'x', 'seed': 1.5}, prefix='~')
    for name in ('~cmd_timeout', '~wheel_radius', '~gyro_bias', '~seed'):
        assert name in str(err.value)


@settings(max_examples=100, deadline=None)
@given(st.sampled_from(sorted(LIMITS)), st.booleans(),
       st.lists(st.tuples(st.floats(), st.floats(), st.floats(1e-6, 100.0)),
                min_size=1, max_size=10))
def test_config_at_its_limits_keeps_the_model_finite(field, at_max, commands):
    low, high = LIMITS[field]
    extreme = high if at_max else (low if low != 0 else 1e-300)
    values = dict(seed=0, encoder_noise=1.0, gyro_noise_density=10.0,
                  max_linear_speed=100.0, max_angular_speed=100.0,
                  wheel_separation=10.0)
    values[field] = extreme
    sim = DiffDriveSim(DiffDriveConfig(**values))
    for _ in replay(sim, commands):
        pass
    for value in (sim.truth.x, sim.truth.y, sim.odom.x, sim.odom.y, sim.odom.yaw,
                  sim.gyro_yaw, sim.gyro_rate, *sim.wheel_angles, *sim.wheel_velocities,
                  *sim.odom_velocity):
        assert math.isfinite(value)
