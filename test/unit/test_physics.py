"""Unit tests for rbx1_nav.sim.physics: the TurtleBot with real dynamics
on MuJoCo (no master). The model tests need MuJoCo (`make deps` installs
it); the configuration tests run without it."""
import builtins
import math
import xml.etree.ElementTree as ElementTree

import pytest

from rbx1_nav.sim.diff_drive import DiffDriveConfig, DiffDriveFleet
from rbx1_nav.sim.physics import (INSTALL_HINT, URDF, Body, PhysicsConfig,
                                  PhysicsFleet)

def mujoco_or_skip():
    pytest.importorskip('mujoco', reason=INSTALL_HINT)


def drive(fleet, commands, seconds, start=0.0, rate=50.0):
    """Command each robot (v, w) (``commands``, one pair per robot) every
    1/rate s for ``seconds``; returns the time reached."""
    t = start
    if fleet._time is None:
        fleet.step(t)
    for _ in range(int(round(seconds * rate))):
        for robot, (v, w) in enumerate(commands):
            if v is not None:
                fleet.command(robot, v, w, t)
        t += 1.0 / rate
        fleet.step(t)
    return t


# -- the URDF is the model's source ------------------------------------------

def test_the_urdf_gives_the_casters_masses_and_the_nominal_geometry():
    body = Body.from_urdf(URDF)
    assert sorted(body.casters) == [(-0.13, -0.016, 0.015), (0.13, -0.018, 0.015)]
    assert body.base_mass + 2 * body.wheel_mass == pytest.approx(PhysicsConfig().mass)
    joints = {j.get('name'): j for j in ElementTree.parse(URDF).getroot().iter('joint')}
    left_y = float(joints['left_wheel_joint'].find('origin').get('xyz').split()[1])
    right_y = float(joints['right_wheel_joint'].find('origin').get('xyz').split()[1])
    axle = float(joints['base_footprint_joint'].find('origin').get('xyz').split()[2])
    assert left_y - right_y == pytest.approx(DiffDriveConfig().wheel_separation)
    assert axle == pytest.approx(DiffDriveConfig().wheel_radius)


# -- bad input: one clear error ------------------------------------------------

def test_an_unknown_floor_is_named_with_the_choices():
    problems = PhysicsConfig(floor='wood').problems()
    assert problems == ["floor must be one of carpet, tile, got 'wood'"]
    with pytest.raises(ValueError, match="~floor must be one of carpet, tile"):
        PhysicsConfig.from_params({'floor': 'wood'}, prefix='~')


@pytest.mark.parametrize('name, value', [('mass', 0.0), ('mass', -6.0),
                                         ('wheel_radius', -0.033),
                                         ('motor_torque', 0.0),
                                         ('encoder_ticks', 0.5)])
def test_impossible_physical_values_are_refused(name, value):
    with pytest.raises(ValueError, match='~%s must be' % name):
        PhysicsConfig.from_params({name: value}, prefix='~')


def test_a_mass_the_wheels_outweigh_is_refused():
    mujoco_or_skip()
    with pytest.raises(ValueError, match="mass must exceed the two wheels' 0.2 kg"):
        PhysicsFleet(1, PhysicsConfig(mass=0.15))


def test_motors_too_weak_to_move_the_robot_are_refused():
    mujoco_or_skip()
    with pytest.raises(ValueError, match='motor_torque 0.001 N m cannot move '
                                         'the 6 kg robot on carpet.*raise ~motor_torque'):
        PhysicsFleet(1, PhysicsConfig(motor_torque=0.001))


def test_without_mujoco_one_line_says_how_to_install_it(monkeypatch):
    real_import = builtins.__import__

    def no_mujoco(name, *args, **kwargs):
        if name == 'mujoco':
            raise ImportError('No module named mujoco')
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, '__import__', no_mujoco)
    with pytest.raises(ImportError) as err:
        PhysicsFleet(1)
    assert str(err.value) == INSTALL_HINT
    assert 'pip install mujoco' in INSTALL_HINT
    # The kinematic robot does not need it.
    fleet = DiffDriveFleet(1)
    drive(fleet, [(0.2, 0.0)], 1.0)
    assert fleet.truth[0, 0] == pytest.approx(0.2)


# -- the dynamics -------------------------------------------------------------

def test_on_tile_the_robot_drives_as_commanded_and_odometry_follows():
    mujoco_or_skip()
    fleet = PhysicsFleet(1, PhysicsConfig(floor='tile'))
    t = drive(fleet, [(0.2, 0.0)], 5.0)
    x = fleet.truth[0, 0]
    assert 0.9 < x < 1.0           # it takes time to speed up (inertia)
    assert fleet.odom[0, 0] == pytest.approx(x, rel=0.01)
    assert fleet.velocity[0, 0] == pytest.approx(0.2, rel=0.05)
    drive(fleet, [(None, None)], 2.0, start=t)  # no commands: the watchdog stops it
    assert bool(fleet.timed_out[0])
    assert abs(fleet.velocity[0, 0]) < 1e-3
    assert fleet.truth[0, 0] > x   # it coasted on after the last command


def test_a_turn_at_the_book_speed_coasts_past_the_stop():
    mujoco_or_skip()
    fleet = PhysicsFleet(1, PhysicsConfig(floor='carpet'))
    t = drive(fleet, [(0.0, 1.0)], 1.0)
    at_stop = fleet.truth[0, 2]
    drive(fleet, [(0.0, 0.0)], 1.0, start=t)
    coast = math.degrees(math.remainder(fleet.truth[0, 2] - at_stop, 2 * math.pi))
    assert 1.0 < coast < 10.0


def test_a_wheel_command_inside_the_deadband_does_not_move_the_robot():
    mujoco_or_skip()
    fleet = PhysicsFleet(1, PhysicsConfig(motor_deadband=0.2))
    start = fleet.truth.copy()
    drive(fleet, [(0.0, 0.04)], 3.0)  # 0.16 rad/s at each wheel
    assert fleet.truth[0] == pytest.approx(start[0], abs=1e-5)
    drive(fleet, [(0.0, 0.1)], 3.0, start=3.0)  # 0.39 rad/s: it turns
    assert fleet.truth[0, 2] > 0.1


def test_a_larger_right_wheel_curves_left_while_odometry_says_straight():
    mujoco_or_skip()
    fleet = PhysicsFleet(1, PhysicsConfig(right_wheel_radius_error=1.02, floor='tile'))
    drive(fleet, [(0.2, 0.0)], 5.0)
    assert fleet.truth[0, 2] > math.radians(3)
    assert abs(fleet.odom[0, 2]) < math.radians(0.2)


def test_encoders_count_whole_ticks():
    mujoco_or_skip()
    fleet = PhysicsFleet(1, PhysicsConfig(encoder_ticks=100))
    drive(fleet, [(0.1, 0.3)], 1.3)
    ticks = fleet.wheel_angles[0] / (2 * math.pi / 100)
    assert ticks == pytest.approx(ticks.round(), abs=1e-6)
    assert all(ticks > 10)


def test_robots_of_a_fleet_do_not_touch_and_match_a_robot_alone():
    mujoco_or_skip()
    fleet = PhysicsFleet(2)
    drive(fleet, [(0.0, 0.0), (0.15, 0.5)], 3.0)
    alone = PhysicsFleet(1)
    drive(alone, [(0.15, 0.5)], 3.0)
    assert fleet.truth[0] == pytest.approx([0, 0, 0], abs=1e-4)
    assert fleet.truth[1] == pytest.approx(alone.truth[0], abs=1e-6)
    assert fleet.odom[1] == pytest.approx(alone.odom[0], abs=1e-9)


def test_the_truth_read_after_many_steps_is_the_last_steps():
    """truth and velocity come from MuJoCo's state when read: read once at
    the end, they are what reading them after every step gives."""
    mujoco_or_skip()
    watched, unwatched = PhysicsFleet(1), PhysicsFleet(1)
    readings = []
    t = 0.0
    for fleet in (watched, unwatched):
        fleet.step(0.0)
    for i in range(100):
        t += 0.02
        for fleet in (watched, unwatched):
            fleet.command(0, 0.2, 0.6 if i < 50 else -0.4, t)
            fleet.step(t)
        readings.append((watched.truth.copy(), watched.velocity.copy()))
    assert readings[-1][0][0] == pytest.approx(unwatched.truth[0], abs=0.0)
    assert readings[-1][1][0] == pytest.approx(unwatched.velocity[0], abs=0.0)
    assert unwatched.odom[0] == pytest.approx(watched.odom[0], abs=0.0)
    # ... and they moved with the robot: each step's reading is its own.
    assert readings[0][0][0, 0] < readings[-1][0][0, 0]
    assert readings[40][1][0, 1] > 0 > readings[-1][1][0, 1]
