"""Unit tests for rbx1_nav.calibration.scale: the tests' courses and the arithmetic."""
import ast
import math
import os

import pytest

from ideal_robot import IdealRobot, run
from rbx1_nav.calibration.scale import (ANGULAR, LINEAR, USUAL, Answers, PoseTrack,
                                        correction, course, far_from_one, measure,
                                        measured_refusal, report)
from rbx1_nav.sim.diff_drive import DiffDriveConfig
from rbx1_nav.transform_utils import Pose2D, normalize_angle

LINEAR_CONFIG = {'test_distance': 1.0, 'speed': 0.15, 'tolerance': 0.01,
                 'odom_linear_scale_correction': 1.0}
ANGULAR_CONFIG = {'test_angle': 360.0, 'speed': 0.5, 'tolerance': 1.0,
                  'odom_angular_scale_correction': 1.0}


class MiscalibratedOdometry(object):
    """What a driver reports for an IdealRobot: distance x ``linear``,
    rotation x ``angular`` (the fake robot's *_scale_error)."""

    def __init__(self, robot, linear=1.0, angular=1.0):
        self.robot, self.linear, self.angular = robot, linear, angular
        self.x = self.y = self.yaw = 0.0
        self.last = None

    @property
    def pose(self):
        true = (self.robot.x, self.robot.y, self.robot.yaw)
        if self.last is not None:
            dx, dy = true[0] - self.last[0], true[1] - self.last[1]
            ds = math.hypot(dx, dy) * self.linear
            self.yaw += (true[2] - self.last[2]) * self.angular
            self.x += ds * math.cos(self.yaw)
            self.y += ds * math.sin(self.yaw)
        self.last = true
        return Pose2D(self.x, self.y, normalize_angle(self.yaw))

    def step(self, cmd, dt):
        self.robot.step(cmd, dt)


def calibrate(kind, config, linear=1.0, angular=1.0):
    """Run the test on a miscalibrated ideal robot; return the correction."""
    robot = IdealRobot()
    odometry = MiscalibratedOdometry(robot, linear, angular)
    test = course(kind, config, settle=1.0)
    run(test, odometry)
    odom_value = measure(kind, test.start_pose, odometry.pose, test.yaw_total)
    truth = measure(kind, Pose2D(0, 0, 0), robot.pose, robot.yaw)
    return correction(kind, odom_value, truth), odom_value


@pytest.mark.parametrize('error', [0.9, 1.0, 1.07])
def test_linear_test_finds_the_inverse_of_the_distance_error(error):
    factor, odom = calibrate(LINEAR, LINEAR_CONFIG, linear=error)
    assert factor == pytest.approx(1.0 / error, rel=1e-6)
    assert 0.99 <= odom <= 1.0 + 0.15 * 0.05  # stops within the tolerance


@pytest.mark.parametrize('error', [0.93, 1.0, 1.05])
def test_angular_test_finds_the_inverse_of_the_rotation_error(error):
    factor, odom = calibrate(ANGULAR, ANGULAR_CONFIG, angular=error)
    assert factor == pytest.approx(1.0 / error, rel=1e-6)
    assert 359.0 <= odom < 360.0 + math.degrees(0.5 * 0.05)


def test_the_node_side_correction_scales_the_goal():
    # With the right correction set in the node, the robot covers the true
    # test distance although odometry over-reports it.
    config = dict(LINEAR_CONFIG, odom_linear_scale_correction=1 / 1.07,
                  tolerance=0.0)
    robot = IdealRobot()
    run(course(LINEAR, config, settle=0.0), MiscalibratedOdometry(robot, 1.07))
    assert robot.x == pytest.approx(1.0, abs=0.15 * 0.05)


def test_with_a_candidate_factor_in_the_node_the_report_gives_the_residual():
    # Odometry over-reports rotation by 5 %; the node already applies 0.95.
    lines, warning = report(ANGULAR, 380.0, 361.0, 'ground truth',
                            node_factor=0.95)
    assert warning is None
    assert 'x this node\'s odom_angular_scale_correction 0.9500 = 361.0000 deg' \
        in lines[0]
    assert lines[1].endswith('= 361.0000 / 361.0000 = 1.0000')
    assert "current value x 0.9500 (this node's 0.9500 x 1.0000)" in lines[2]


def test_pose_track_counts_a_full_turn_as_360_degrees():
    track = PoseTrack()
    for k in range(37):
        track.add(Pose2D(0.0, 0.0, normalize_angle(math.radians(10.0 * k))))
    assert track.value(ANGULAR) == pytest.approx(360.0)
    assert track.value(LINEAR) == 0.0
    track.add(Pose2D(3.0, 4.0, 0.0))
    assert track.value(LINEAR) == pytest.approx(5.0)


def test_report_shows_the_arithmetic_and_the_value_to_set():
    lines, _ = report(LINEAR, 1.07, 1.0, 'ground truth')
    assert lines[0] == ('linear test: odometry 1.0700 m, measured 1.0000 m '
                        '(ground truth)')
    assert lines[1] == ('odom_linear_scale_correction = measured / odometry = '
                        '1.0000 / 1.0700 = 0.9346')
    assert '0.9346' in lines[2] and 'driver' in lines[2]
    assert 'odom_angular_scale_correction' in report(ANGULAR, 360, 380, 'x')[0][1]


@pytest.mark.parametrize('odometry, measured, words', [
    (1.0, float('nan'), 'measured distance must be a positive number'),
    (1.0, float('inf'), 'measured distance must be a positive number'),
    (1.0, -1.0, 'measured distance must be a positive number'),
    (1.0, 0.0, 'measured distance must be a positive number'),
    (0.0, 1.0, 'odometry distance must be a positive number'),
    (1.0, 0.002, r'under 1/100 of what odometry reports .*: the robot did not move'),
    (0.005, 1.0, r'odometry did not see the robot move'),
    (1.0, 'one', 'measured distance must be a positive number'),
])
def test_unusable_measurements_are_refused_with_the_reason(odometry, measured,
                                                           words):
    with pytest.raises(ValueError, match=words):
        report(LINEAR, odometry, measured, 'tape')


@pytest.mark.parametrize('kind, odometry, measured', [
    (ANGULAR, 360.0, 106.0),  # the Husky (skid steer): 0.29
    (ANGULAR, 360.0, 1080.0),
    (LINEAR, 1.0, 0.3),
    (LINEAR, 1.0, 3.0),
])
def test_a_factor_far_from_one_is_given_with_a_warning_naming_the_causes(
        kind, odometry, measured):
    lines, warning = report(kind, odometry, measured, 'ground truth')
    factor = measured / odometry
    assert lines[1].endswith('= %.4f' % factor)
    assert 'typo' not in warning and 'Usual causes' in warning
    assert '%s %.4f is far from 1' % (kind.correction, factor) in warning
    assert ('skid-steer' in warning and 'wheel base' in warning) \
        if kind is ANGULAR else 'wheel radius' in warning
    assert 'wrong unit (give %s)' % kind.unit_name in warning


def test_usual_factors_get_no_warning():
    for factor in (USUAL[0], 0.95, 1.0, 1.07, USUAL[1]):
        assert far_from_one(ANGULAR, factor) is None
    assert far_from_one(LINEAR, USUAL[0] - 0.01) is not None
    assert far_from_one(LINEAR, USUAL[1] + 0.01) is not None


def test_an_angle_in_radians_gets_a_factor_with_the_unit_warning():
    factor = correction(ANGULAR, 360.0, 2 * math.pi)
    assert factor == pytest.approx(2 * math.pi / 360.0)
    assert 'wrong unit (give degrees)' in far_from_one(ANGULAR, factor)


def _cfg_limits(name, field):
    """(default, min, max) of ``field`` in cfg/``name``.cfg."""
    path = os.path.join(os.path.dirname(__file__), '..', '..', 'cfg',
                        name + '.cfg')
    with open(path) as f:
        tree = ast.parse(f.read())
    for node in ast.walk(tree):
        if (isinstance(node, ast.Call) and getattr(node.func, 'attr', '') == 'add'
                and ast.literal_eval(node.args[0]) == field):
            return tuple(ast.literal_eval(a) for a in node.args[4:7])
    raise AssertionError('%s not in %s.cfg' % (field, name))


@pytest.mark.parametrize('factor', [0.3, 0.5, 1.875, 3.0])
def test_the_config_fields_and_the_driver_take_factors_far_from_one(factor):
    for cfg, kind in (('CalibrateLinear', LINEAR), ('CalibrateAngular', ANGULAR)):
        _, low, high = _cfg_limits(cfg, kind.correction)
        assert low <= factor <= high
        goal_max = _cfg_limits(cfg, kind.goal)[2]
        assert _cfg_limits(cfg, kind.measured)[2] >= 3.0 * goal_max
    config = DiffDriveConfig.from_params({
        'odom_linear_scale_correction': factor,
        'odom_angular_scale_correction': factor,
        'wheel_separation_multiplier': factor})
    assert config.problems() == []


@pytest.mark.parametrize('kind, value', [(LINEAR, -1.0), (LINEAR, float('nan')),
                                         (ANGULAR, -352.0), (ANGULAR, float('inf'))])
def test_a_measurement_that_is_not_positive_is_refused_naming_it(kind, value):
    line = measured_refusal(kind, value, '/calibrate_' + kind.name)
    assert line.startswith('%s %r refused: ' % (kind.measured, value))
    assert 'must be a positive number of %s' % kind.unit_name in line
    assert ('dynparam set /calibrate_%s %s ' % (kind.name, kind.measured)) in line


@pytest.mark.parametrize('kind, value', [(LINEAR, 0.97), (LINEAR, 1e-6),
                                         (ANGULAR, 352.0), (ANGULAR, 4000.0)])
def test_a_positive_measurement_is_not_refused(kind, value):
    assert measured_refusal(kind, value, '/n') is None


def configs(kind, answers, *changes):
    """Feed ``answers`` the configurations a server would hold after each
    change (a dict of fields), starting from its defaults; return the last
    configuration kept and the notes."""
    config = {'start_test': False, kind.measured: 0.0}
    notes = []
    for change in changes:
        config = dict(config, **change)
        notes.append(answers.reconfigured(config))
    return config, notes


@pytest.mark.parametrize('kind, value', [(LINEAR, 0.97), (ANGULAR, 352.0)])
def test_a_measurement_typed_while_the_test_runs_is_kept_for_its_end(kind, value):
    answers = Answers(kind, '/calibrate_' + kind.name)
    config, notes = configs(kind, answers, {'start_test': True},
                            {kind.measured: value})
    assert notes[0] is None
    assert notes[1] == ('info', '%s %g kept: the test is still running; it is used '
                        'when the test ends, as if given after "odometry says"'
                        % (kind.measured, value))
    assert config[kind.measured] == value  # the field shows it, as after the end
    # The node takes it once the test has ended, and only once.
    config = dict(config, start_test=False)
    assert answers.reconfigured(config) is None
    assert config[kind.measured] == value
    assert answers.take() == value
    assert answers.take() == 0.0


def test_a_test_start_clears_the_field_so_the_same_number_typed_again_counts():
    answers = Answers(LINEAR, '/calibrate_linear')
    config, _ = configs(LINEAR, answers, {'measured_distance': 0.97})
    assert answers.take() == 0.97  # for the test before
    config, _ = configs(LINEAR, answers, dict(config, start_test=True))
    assert config['measured_distance'] == 0.0
    configs(LINEAR, answers, dict(config, measured_distance=0.97))
    assert answers.take() == 0.97


def test_a_value_typed_just_before_a_start_still_belongs_to_the_test_before():
    answers = Answers(LINEAR, '/calibrate_linear')
    config, _ = configs(LINEAR, answers, {'measured_distance': 0.97},
                        {'start_test': True})
    assert config['measured_distance'] == 0.0
    assert answers.take() == 0.97


@pytest.mark.parametrize('kind, value', [(LINEAR, -1.0), (ANGULAR, float('nan'))])
def test_a_refused_value_is_refused_at_once_during_a_test_too(kind, value):
    for start in (False, True):
        answers = Answers(kind, '/calibrate_' + kind.name)
        config, notes = configs(kind, answers, {'start_test': start},
                                {kind.measured: value})
        level, line = notes[-1]
        assert level == 'warn'
        assert line == measured_refusal(kind, value, '/calibrate_' + kind.name)
        assert config[kind.measured] == 0.0
        assert answers.take() == 0.0


def test_zero_takes_back_a_value_not_used_yet_and_other_fields_give_nothing():
    answers = Answers(LINEAR, '/calibrate_linear')
    config, notes = configs(LINEAR, answers, {'start_test': True},
                            {'measured_distance': 0.97}, {'measured_distance': 0.0},
                            {'speed': 0.2})
    assert notes[2:] == [None, None]
    assert answers.take() == 0.0
