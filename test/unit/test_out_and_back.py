"""Unit tests for rbx1_nav.motion.course.book: the course state machine, no ROS.

An idealised robot integrates each command for one control period; the
tests check what a user would see: the legs in order, the pauses, the
distances and turns, and where the robot ends up.
"""
import math
from types import SimpleNamespace

import pytest
from hypothesis import given, settings, strategies as st

from ideal_robot import DT, IdealRobot, run
from rbx1_nav.common import params
from rbx1_nav.motion.course.book import OUT_AND_BACK
from rbx1_nav.motion.course.command import STOP, Command, pose_error
from rbx1_nav.transform_utils import Pose2D, normalize_angle


def _node_units(settings):
    """``settings`` in the node's units: these tests give angular_tolerance in radians."""
    tolerance = settings.get('angular_tolerance')
    if isinstance(tolerance, float):
        settings['angular_tolerance'] = math.degrees(tolerance)
    return settings


def out_and_back(**settings):
    """The node's out-and-back course of ``settings`` over the book's values."""
    return OUT_AND_BACK.course(**_node_units(settings))


def settings_of(**settings):
    """The out-and-back's checked values of ``settings`` (angular_tolerance in radians)."""
    values = OUT_AND_BACK.values(**_node_units(settings))
    values['angular_tolerance'] = math.radians(values['angular_tolerance'])
    return SimpleNamespace(**values)

def segments(rows):
    """Collapse rows into (kind, start time, end time) runs.

    kind is 'drive', 'turn' or 'stop', from the command actually sent.
    """
    def kind(cmd):
        if cmd == STOP:
            return 'stop'
        return 'drive' if cmd.linear else 'turn'
    runs = []
    for t, _, cmd in rows:
        k = kind(cmd)
        if runs and runs[-1][0] == k:
            runs[-1][2] = t
        else:
            runs.append([k, t, t])
    return [tuple(r) for r in runs]


# --- the book's course ----------------------------------------------------

def test_default_course_is_the_books():
    cfg = settings_of()
    assert (cfg.linear_speed, cfg.goal_distance, cfg.angular_speed,
            cfg.goal_angle, cfg.legs, cfg.pause) == (0.15, 1.0, 0.5, math.pi,
                                                     2, 1.0)
    assert cfg.angular_tolerance == pytest.approx(math.radians(1.0))
    assert cfg.precise is False


def test_legs_run_in_order_with_pauses_between():
    rows = run(out_and_back(), IdealRobot())
    kinds = [k for k, _, _ in segments(rows)]
    assert kinds == ['drive', 'stop', 'turn', 'stop'] * 2


def test_each_pause_lasts_about_one_second():
    runs = segments(run(out_and_back(), IdealRobot()))
    for kind, start, end in runs:
        if kind == 'stop':
            # end is the last stopped cycle; the next command follows DT later
            assert 1.0 <= end - start + DT <= 1.0 + 2 * DT


def test_drive_covers_goal_distance_at_linear_speed():
    rows = run(out_and_back(), IdealRobot())
    drives = [cmd for _, _, cmd in rows if cmd.linear]
    assert all(cmd == Command(0.15, 0.0) for cmd in drives)
    # Stops on the first reading at or past 1 m: one cycle of travel at most.
    per_leg = len(drives) / 2.0
    assert 1.0 <= per_leg * 0.15 * DT <= 1.0 + 0.15 * DT + 1e-9


def test_turn_is_pi_at_angular_speed_within_tolerance():
    m = out_and_back()
    robot = IdealRobot()
    rows = run(m, robot)
    turns = [cmd for _, _, cmd in rows if cmd.angular]
    assert all(cmd == Command(0.0, 0.5) for cmd in turns)
    per_turn = 0.5 * DT * len(turns) / 2.0
    assert math.pi - math.radians(1.0) <= per_turn
    assert per_turn < math.pi - math.radians(1.0) + 0.5 * DT + 1e-9


def test_ideal_robot_ends_near_start():
    m = out_and_back()
    robot = IdealRobot()
    run(m, robot)
    dist, heading = pose_error(robot.pose, Pose2D(0.0, 0.0, 0.0))
    # One control step of travel (7.5 mm) and the 1 degree tolerance per turn.
    assert dist < 0.02
    assert abs(math.degrees(heading)) < 2 * 1.0 + 0.1


def test_commands_after_done_are_stop():
    m = out_and_back(legs=1)
    robot = IdealRobot()
    rows = run(m, robot)
    assert rows[-1][2] == STOP
    assert m.done and m.phase == 'done'
    for k in range(5):
        assert m.update(robot.pose, 1000.0 + k) == STOP
    assert m.elapsed == pytest.approx(rows[-1][0] - rows[0][0])


def test_last_commands_before_done_are_a_full_pause_of_stops():
    rows = run(out_and_back(), IdealRobot())
    kind, start, end = segments(rows)[-1]
    assert kind == 'stop' and end - start + DT >= 1.0


def test_progress_events_name_each_leg():
    m = out_and_back()
    run(m, IdealRobot())
    events = m.pop_events()
    assert [e.split(':')[0] for e in events[:4]] == [
        'leg 1/2', 'leg 1/2', 'leg 2/2', 'leg 2/2']
    assert 'drove 1.0' in events[0] and 'turned 17' in events[1]
    assert events[-1].startswith('course done in')
    assert m.pop_events() == []


# --- distance and turn bookkeeping ------------------------------------------

def test_distance_is_euclidean_from_leg_start_in_any_direction():
    heading = math.radians(135.0)
    m = out_and_back(goal_distance=0.5, legs=1)
    robot = IdealRobot(Pose2D(3.0, -2.0, heading))
    run(m, robot)
    # The turn back is in place, so the drive alone moved the robot 0.5 m.
    assert math.hypot(robot.x - 3.0, robot.y + 2.0) == pytest.approx(0.5, abs=0.0076)


def test_negative_distance_drives_backwards():
    m = out_and_back(goal_distance=-0.3, goal_angle=0.0, legs=1)
    robot = IdealRobot()
    rows = run(m, robot)
    assert all(cmd.linear <= 0 for _, _, cmd in rows)
    assert robot.x == pytest.approx(-0.3, abs=0.0076)


def feed_yaws(machine, yaws, t0=0.0):
    """Feed yaw readings in place (no travel); return commands in turn phase."""
    t = t0
    out = []
    for yaw in yaws:
        cmd = machine.update(Pose2D(0.0, 0.0, yaw), t)
        out.append((machine.phase, cmd))
        t += DT
    return out


def turning_machine(**kwargs):
    """A machine with a zero-length drive and no pause: it turns at once."""
    return out_and_back(goal_distance=0.0, pause=0.0, legs=1, **kwargs)


def test_turn_accumulates_across_the_pi_wrap():
    m = turning_machine(goal_angle=math.radians(90.0), angular_tolerance=0.0)
    start = math.radians(150.0)
    # 150 deg -> 180 -> -150 (=210) -> -120 (=240): 90 deg turned.
    yaws = [start, start] + [normalize_angle(start + math.radians(d))
                             for d in (30.0, 60.0, 89.0, 90.0)]
    out = feed_yaws(m, yaws)
    assert [cmd.angular > 0 for _, cmd in out[1:5]] == [True] * 4
    assert out[5][1] == STOP  # the reading of exactly 90 deg ends the turn
    assert m.turned == pytest.approx(math.radians(90.0))


def test_tolerance_rule_stops_when_turned_plus_tolerance_reaches_goal():
    tol = math.radians(5.0)
    m = turning_machine(goal_angle=math.radians(60.0), angular_tolerance=tol)
    degrees = [0, 0, 20, 40, 54.9, 55.0, 60.0]
    out = feed_yaws(m, [math.radians(d) for d in degrees])
    assert out[4][1].angular > 0       # 54.9 + 5 < 60: keep turning
    assert out[5][1] == STOP           # 55 + 5 >= 60: stop
    assert out[5][0] == 'pause'
    assert feed_yaws(m, [math.radians(55.0)], t0=1.0) == [('done', STOP)]


def test_tolerance_is_mirrored_for_clockwise_turns():
    tol = math.radians(5.0)
    m = turning_machine(goal_angle=math.radians(-60.0), angular_tolerance=tol)
    degrees = [0, 0, -20, -54.9, -55.0]
    out = feed_yaws(m, [math.radians(d) for d in degrees])
    assert out[2][1].angular < 0 and out[3][1].angular < 0
    assert out[4][1] == STOP


@pytest.mark.parametrize('goal_deg', [180.0, 270.0, 360.0, 450.0, -540.0])
def test_turns_of_pi_and_more_complete(goal_deg):
    goal = math.radians(goal_deg)
    m = out_and_back(goal_distance=0.0, goal_angle=goal, legs=1,
                 angular_tolerance=0.0)
    robot = IdealRobot(Pose2D(0.0, 0.0, math.radians(170.0)))
    run(m, robot)
    assert m.turned == pytest.approx(goal, abs=0.5 * DT + 1e-9)
    assert robot.yaw - math.radians(170.0) == pytest.approx(goal, abs=0.5 * DT + 1e-9)


def test_rotation_while_stopping_counts_towards_the_turn():
    # The book measures the turn from the last reading of the drive.
    m = out_and_back(goal_distance=0.1, goal_angle=math.radians(90),
                 angular_tolerance=0.0, legs=1)
    t = 0.0
    m.update(Pose2D(0.0, 0.0, 0.0), t)
    m.update(Pose2D(0.1, 0.0, 0.0), t + DT)          # goal reached -> pause
    assert m.phase == 'pause'
    m.update(Pose2D(0.1, 0.0, math.radians(30)), t + 0.5)  # drifted 30 deg
    m.update(Pose2D(0.1, 0.0, math.radians(30)), t + 1.1)  # pause over
    assert m.phase == 'turn'
    assert m.turned == pytest.approx(math.radians(30))


# --- precise mode -----------------------------------------------------------

def precise_run(robot, **kwargs):
    m = out_and_back(precise=True, **kwargs)
    rows = run(m, robot)
    return m, rows


def test_precise_mode_slows_down_near_each_goal_but_not_below_creep():
    cfg = settings_of(precise=True)
    m, rows = precise_run(IdealRobot())
    linear = [cmd.linear for _, _, cmd in rows if cmd.linear]
    angular = [cmd.angular for _, _, cmd in rows if cmd.angular and not cmd.linear]
    assert max(linear) == pytest.approx(cfg.linear_speed)
    assert min(linear) == pytest.approx(cfg.precise_min_linear_speed)
    assert max(angular) == pytest.approx(cfg.angular_speed)
    assert min(angular) == pytest.approx(cfg.precise_min_angular_speed)
    # Within each drive, speed never rises again once it starts to fall.
    drives = [[cmd.linear for _, _, cmd in rows if cmd.linear][:len(linear) // 2]]
    for speeds in drives:
        peak = speeds.index(max(speeds))
        tail = speeds[peak:]
        assert all(a >= b for a, b in zip(tail, tail[1:]))


def test_precise_mode_ends_at_odometry_resolution():
    robot = IdealRobot(delay=1)
    m, _ = precise_run(robot)
    dist, heading = pose_error(robot.pose, Pose2D(0.0, 0.0, 0.0))
    assert dist < 0.001
    assert abs(math.degrees(heading)) < 0.1


def test_precise_mode_beats_the_book_mode_on_a_lagging_robot():
    book, precise = IdealRobot(delay=1), IdealRobot(delay=1)
    run(out_and_back(), book)
    precise_run(precise)
    book_err = pose_error(book.pose, Pose2D(0, 0, 0))
    precise_err = pose_error(precise.pose, Pose2D(0, 0, 0))
    assert precise_err[0] < book_err[0] / 5
    assert abs(precise_err[1]) < abs(book_err[1]) / 5


def test_precise_mode_holds_heading_against_drift():
    drift = math.radians(2.0)  # rad/s of yaw while driving
    robot = IdealRobot(yaw_rate_bias=drift)
    m, rows = precise_run(robot, legs=1, goal_angle=0.0)
    corrections = [cmd.angular for _, _, cmd in rows if cmd.linear]
    assert corrections[-1] < 0  # steering against the drift
    assert abs(robot.y) < 0.015
    # Without heading hold the same drift bends the path much further.
    book = IdealRobot(yaw_rate_bias=drift)
    run(out_and_back(legs=1, goal_angle=0.0), book)
    assert abs(book.y) > 5 * abs(robot.y)


# --- ends and bad input -----------------------------------------------------

@given(x=st.floats(-50, 50), y=st.floats(-50, 50),
       yaw=st.floats(-math.pi, math.pi),
       distance=st.floats(-2.0, 2.0), angle=st.floats(-7.0, 7.0),
       legs=st.integers(1, 4))
@settings(max_examples=30, deadline=None)
def test_ideal_robot_precise_course_ends_where_expected(x, y, yaw, distance,
                                                        angle, legs):
    start = Pose2D(x, y, yaw)
    cfg = dict(goal_distance=distance, goal_angle=angle, legs=legs, precise=True, pause=0.1)
    robot = IdealRobot(start)
    run(out_and_back(**cfg), robot, limit=3000.0)
    dist, heading = pose_error(robot.pose, out_and_back(**cfg).ideal_end(start))
    assert dist < 0.002 * legs
    assert abs(heading) < 0.001 * legs


def test_expected_end_pose_of_the_books_course_is_the_start():
    start = Pose2D(1.0, 2.0, 0.3)
    end = out_and_back().ideal_end(start)
    dist, heading = pose_error(end, start)
    assert dist == pytest.approx(0.0, abs=1e-12)
    assert heading == pytest.approx(0.0, abs=1e-12)


def test_expected_end_pose_of_a_square():
    end = out_and_back(goal_angle=math.pi / 2, legs=3).ideal_end(Pose2D(0, 0, 0))
    assert end.x == pytest.approx(0.0, abs=1e-12)
    assert end.y == pytest.approx(1.0)
    assert end.yaw == pytest.approx(-math.pi / 2)


@pytest.mark.parametrize('field, value, words', [
    ('linear_speed', 0.0, r'linear_speed must be > 0 and <= 2,'),
    ('linear_speed', -0.1, r'linear_speed must be > 0'),
    ('angular_speed', float('nan'), 'angular_speed must be a finite number'),
    ('goal_distance', float('inf'), 'goal_distance must be a finite number'),
    ('goal_angle', 'pi', 'goal_angle must be a number'),
    ('angular_tolerance', -1.0, 'angular_tolerance must be >= 0'),
    ('legs', 0, 'legs must be an integer >= 1 and <= 1000'),
    ('legs', 1.5, 'legs must be an integer'),
    ('legs', True, 'legs must be a number'),
    ('pause', float('nan'), 'pause must be a finite number'),
    ('precise_min_linear_speed', 0.0, 'precise_min_linear_speed must be > 0'),
    ('precise', 'yes', 'precise must be true or false'),
    ('linear_speed', 100.0, 'linear_speed must be > 0 and <= 2,'),
    ('angular_speed', 50.0, r'angular_speed must be > 0 and <= 6.28'),
    ('legs', 10 ** 9, 'legs must be an integer >= 1 and <= 1000'),
])
def test_absurd_settings_are_rejected_by_name(field, value, words):
    with pytest.raises(ValueError, match=words):
        out_and_back(**{field: value})


def test_numeric_strings_are_accepted_and_converted():
    # rosparam reads 1e-1 as a string; the checks accept it as a number.
    cfg = settings_of(linear_speed='1e-1', legs='3')
    assert cfg.linear_speed == 0.1 and cfg.legs == 3


def test_all_problems_are_reported_together():
    problems = params.read_all(OUT_AND_BACK.params, dict(linear_speed=0.0, legs=0).get)[1]
    assert len(problems) == 2


def test_non_finite_pose_is_rejected():
    m = out_and_back()
    m.update(Pose2D(0.0, 0.0, 0.0), 0.0)
    with pytest.raises(ValueError, match='non-finite'):
        m.update(Pose2D(float('nan'), 0.0, 0.0), DT)


def test_first_command_is_forward_at_linear_speed():
    m = out_and_back()
    assert m.update(Pose2D(0.0, 0.0, 0.0), 5.0) == Command(0.15, 0.0)
    assert m.start_pose == Pose2D(0.0, 0.0, 0.0) and m.steps[m.index].label == 'leg 1/2'
