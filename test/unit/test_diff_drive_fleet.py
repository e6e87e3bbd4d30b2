"""Unit tests for rbx1_nav.sim.diff_drive.DiffDriveFleet, N bases in arrays
(the model of nodes/fake_fleet.py; no master)."""
import math
import random

import numpy as np
import pytest

from rbx1_nav.sim.diff_drive import DiffDriveConfig, DiffDriveFleet, DiffDriveSim

RATE = 50.0
TOLERANCE = 1e-12  # the fleet must step each robot as the single model does

# Every deterministic part of the model in use: speed and acceleration
# limits, latency, scale errors, unequal wheels, the drivers' corrections,
# a gyro bias.
UNCALIBRATED = dict(accel_limit_linear=0.8, accel_limit_angular=3.0,
                    command_latency=0.03, cmd_timeout=0.3,
                    linear_scale_error=1.02, angular_scale_error=0.97,
                    right_wheel_radius_error=1.005,
                    left_wheel_radius_multiplier=0.999,
                    wheel_separation_multiplier=1.01, gyro_bias=0.002)


def state(sim):
    """Every state value of one robot as a flat list of floats."""
    return [*sim.truth, *sim.odom, *sim.velocity, *sim.odom_velocity,
            *sim.wheel_angles, *sim.wheel_velocities, sim.gyro_rate,
            sim.gyro_yaw, float(sim.timed_out)]


def angle_aware_difference(a, b):
    """Largest difference of two state lists (yaw wraps at +-pi)."""
    return max(abs(math.remainder(x - y, 2 * math.pi)) if i in (2, 5, 15)
               else abs(x - y) for i, (x, y) in enumerate(zip(a, b)))


@pytest.mark.parametrize('config', [{}, UNCALIBRATED], ids=['ideal', 'uncalibrated'])
def test_fleet_steps_each_robot_like_a_single_model(config):
    """Five robots with their own random commands, some silent long enough
    for the watchdog, some clamped: each row matches a DiffDriveSim fed the
    same commands, every step."""
    n = 5
    fleet = DiffDriveFleet(n, DiffDriveConfig(**config))
    singles = [DiffDriveSim(DiffDriveConfig(**config)) for _ in range(n)]
    robots = [fleet.robot(i) for i in range(n)]
    rnd = random.Random(12)
    t = 0.0
    assert fleet.step(t) is False
    for single in singles:
        single.step(t)
    worst = 0.0
    for k in range(1500):
        for i in range(n):
            # Robot i commands with probability 0.1 * (i + 1): robot 0
            # is often silent past cmd_timeout, robot 4 hardly ever.
            if rnd.random() < 0.1 * (i + 1):
                v, w = rnd.uniform(-0.7, 0.7), rnd.uniform(-4.0, 4.0)
                stamp = t + rnd.uniform(0.0, 1.0 / RATE)
                assert robots[i].command(v, w, stamp) == singles[i].command(v, w, stamp)
        t += 1.0 / RATE
        assert fleet.step(t) is True
        for i in range(n):
            assert singles[i].step(t) is True
            worst = max(worst, angle_aware_difference(state(robots[i]),
                                                      state(singles[i])))
    assert worst <= TOLERANCE
    # The run did exercise what it claims: robots that moved differently.
    finals = [robots[i].truth for i in range(n)]
    assert len(set(finals)) == n


@pytest.mark.parametrize('config', [{}, UNCALIBRATED, dict(
    UNCALIBRATED, encoder_noise=0.01, gyro_noise_density=0.003, seed=7)],
    ids=['ideal', 'uncalibrated', 'noisy'])
def test_a_single_robot_is_a_fleet_of_one_to_the_last_bit(config):
    """DiffDriveSim (plain floats) and DiffDriveFleet(1) (numpy): the same
    floats at every step, noise, watchdog, clamping, a clock reset and
    commands on the step's own stamp among them."""
    fleet = DiffDriveFleet(1, DiffDriveConfig(**config))
    row, single = fleet.robot(0), DiffDriveSim(DiffDriveConfig(**config))
    rnd = random.Random(3)
    t, moved = 5.0, 0
    for k in range(3000):
        if k == 1800:
            t = 2.0  # the clock restarts from further back
        if rnd.random() < 0.3:
            v, w = rnd.uniform(-0.7, 0.7), rnd.uniform(-4.0, 4.0)
            stamp = t + rnd.choice([0.0, rnd.uniform(0.0, 1.0 / RATE)])
            assert row.command(v, w, stamp) == single.command(v, w, stamp)
        assert fleet.step(t) == single.step(t)
        assert state(row) == state(single), k
        assert row.command_time == single.command_time
        moved += row.velocity != (0.0, 0.0)
        t += 1.0 / RATE
    assert moved > 1000 and single.robot(0) is single
    assert row.gyro_variances(0.02) == single.gyro_variances(0.02)


def test_each_robot_follows_its_own_command():
    fleet = DiffDriveFleet(3)
    fleet.step(0.0)
    for k in range(50):  # 1 s at 50 Hz
        stamp = k / RATE
        fleet.command(0, 0.2, 0.0, stamp)
        fleet.command(1, 0.0, 0.5, stamp)
        fleet.command(2, -0.1, 0.0, stamp)
        fleet.step((k + 1) / RATE)
    assert fleet.truth[0] == pytest.approx([0.2, 0.0, 0.0], abs=1e-9)
    assert fleet.truth[1] == pytest.approx([0.0, 0.0, 0.5], abs=1e-9)
    assert fleet.truth[2] == pytest.approx([-0.1, 0.0, 0.0], abs=1e-9)
    assert fleet.velocity.tolist() == [[0.2, 0.0], [0.0, 0.5], [-0.1, 0.0]]


def test_watchdog_stops_only_the_silent_robot():
    """Robot 1 sends one command; robot 0 keeps sending: after cmd_timeout
    plus one step robot 1 stands still, robot 0 still drives."""
    fleet = DiffDriveFleet(2, DiffDriveConfig(cmd_timeout=0.5))
    fleet.step(0.0)
    fleet.command(1, 0.2, 0.0, 0.0)
    last_moving = None
    for k in range(1, 101):  # 2 s
        fleet.command(0, 0.2, 0.0, (k - 1) / RATE)
        fleet.step(k / RATE)
        if fleet.velocity[1, 0] != 0.0:
            last_moving = k / RATE
    assert fleet.timed_out.tolist() == [False, True]
    assert fleet.velocity.tolist() == [[0.2, 0.0], [0.0, 0.0]]
    assert 0.5 - 1 / RATE <= last_moving <= 0.5 + 1 / RATE
    assert fleet.truth[0, 0] == pytest.approx(0.4, abs=1e-9)
    assert fleet.truth[1, 0] == pytest.approx(0.1, abs=0.2 / RATE)


def test_robots_without_any_command_stand_still():
    fleet = DiffDriveFleet(4)
    fleet.step(0.0)
    fleet.command(2, 0.2, 0.0, 0.0)
    fleet.step(1 / RATE)
    assert fleet.timed_out.tolist() == [True, True, False, True]
    assert fleet.velocity[:, 0].tolist() == [0.0, 0.0, 0.2, 0.0]


@pytest.mark.parametrize('v, w', [(float('nan'), 0.0), (0.1, float('inf')),
                                  (-float('inf'), float('nan'))])
def test_non_finite_command_stops_that_robot_only(v, w):
    fleet = DiffDriveFleet(3)
    fleet.step(0.0)
    for k in range(10):
        for i in range(3):
            fleet.command(i, 0.2, 0.3, k / RATE)
        fleet.step((k + 1) / RATE)
    assert fleet.command(1, v, w, 10 / RATE) == 'non-finite'
    assert fleet.command(0, 0.2, 0.3, 10 / RATE) is None
    assert fleet.command(2, 0.2, 0.3, 10 / RATE) is None
    fleet.step(11 / RATE)
    assert fleet.velocity.tolist() == [[0.2, 0.3], [0.0, 0.0], [0.2, 0.3]]
    for array in (fleet.truth, fleet.odom, fleet.wheel_angles, fleet.gyro_yaw):
        assert np.all(np.isfinite(array))


def test_clamping_is_per_command():
    fleet = DiffDriveFleet(2, DiffDriveConfig(max_linear_speed=0.5,
                                              max_angular_speed=2.0))
    fleet.step(0.0)
    assert fleet.command(0, 1e9, -1e9, 0.0) == 'clamped'
    assert fleet.command(1, 0.1, 0.2, 0.0) is None
    fleet.step(1 / RATE)
    assert fleet.velocity.tolist() == [[0.5, -2.0], [0.1, 0.2]]


def test_time_moving_backwards_drops_every_robots_commands():
    fleet = DiffDriveFleet(2)
    fleet.step(0.0)
    for i in range(2):
        fleet.command(i, 0.2, 0.0, 0.0)
    fleet.step(0.2)
    truth = fleet.truth.copy()
    assert fleet.step(0.1) is False
    assert fleet.step(0.12) is True
    assert fleet.velocity.tolist() == [[0.0, 0.0], [0.0, 0.0]]
    assert fleet.truth.tolist() == truth.tolist()


def test_noise_differs_between_robots_and_repeats_with_the_seed():
    """One generator for the fleet: robots with the same commands drift
    apart, and the same seed gives the same fleet."""
    noise = dict(encoder_noise=0.01, gyro_noise_density=0.01, seed=5)

    def run():
        fleet = DiffDriveFleet(3, DiffDriveConfig(**noise))
        fleet.step(0.0)
        for k in range(100):
            for i in range(3):
                fleet.command(i, 0.3, 0.2, k / RATE)
            fleet.step((k + 1) / RATE)
        return fleet

    a, b = run(), run()
    assert a.odom.tolist() == b.odom.tolist()
    assert a.gyro_yaw.tolist() == b.gyro_yaw.tolist()
    assert len({tuple(row) for row in a.odom.tolist()}) == 3
    assert len(set(a.gyro_yaw.tolist())) == 3
    # The truth has no noise: identical commands, identical true paths.
    assert a.truth[0].tolist() == a.truth[1].tolist() == a.truth[2].tolist()


@pytest.mark.parametrize('size', [0, -1, 1.5, True, '3'])
def test_a_fleet_needs_a_whole_number_of_robots(size):
    with pytest.raises(ValueError, match='at least one robot'):
        DiffDriveFleet(size)


def test_invalid_config_is_rejected_for_a_fleet_too():
    with pytest.raises(ValueError, match='wheel_radius'):
        DiffDriveFleet(3, DiffDriveConfig(wheel_radius=0.0))
