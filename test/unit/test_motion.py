"""Unit tests for the motion core (rbx1_nav.motion.course.course, .steps, .precise,
.in_flight, .stalls): the primitives and the Course, no ROS.

The out-and-back rules are covered in test_out_and_back.py; here the open-
loop steps, the square, and how steps chain.
"""
import math
import re

import pytest
from hypothesis import given, settings, strategies as st

from ideal_robot import DT, IdealRobot, run
from rbx1_nav.common import params
from rbx1_nav.motion.course.command import STOP, Command, pose_error
from rbx1_nav.motion.course.course import Course, legs_course
from rbx1_nav.motion.course.legs_params import legs_params
from rbx1_nav.motion.course.summary import control_rates
from rbx1_nav.motion.course.in_flight import InFlight
from rbx1_nav.motion.course.precise import PRECISE_PARAMS, Approach, approach
from rbx1_nav.motion.course.stalls import Stalls
from rbx1_nav.motion.course.steps import Drive, Pause, TimedDrive, TimedTurn, Turn
from rbx1_nav.transform_utils import Pose2D

PRECISE = Approach(1.0, 4.0, 0.005, 0.01)


def timed_course(angular_speed, rate, legs=2):
    return Course(legs_course(1.0, math.pi, legs, 0.2, angular_speed,
                              pause=1.0, period=1.0 / rate))


@pytest.mark.parametrize('angular_speed', [0.5, 1.0, 1.3])
@pytest.mark.parametrize('rate', [50.0, 20.0, 7.0])
def test_timed_course_ends_at_its_start_on_the_ideal_robot(angular_speed, rate):
    robot = IdealRobot()
    run(timed_course(angular_speed, rate), robot, t0=12.3456, dt=1.0 / rate)
    dist, heading = pose_error(robot.pose, Pose2D(0.0, 0.0, 0.0))
    # Exact up to float rounding: the last command of each move is scaled
    # to the time left in it.
    assert dist < 1e-9
    assert abs(heading) < 1e-9


def test_timed_moves_last_distance_over_speed_and_ignore_odometry():
    course = Course([TimedDrive(1.0, 0.2, DT), TimedTurn(-math.pi / 2, 0.5, DT)])
    rows, t, pose = [], 0.0, Pose2D(5.0, 5.0, 1.0)  # a pose that never changes
    while not course.done:
        rows.append(course.update(pose, t))
        t += DT
    drive = [c.linear for c in rows if c.linear]
    turn = [c.angular for c in rows if c.angular]
    assert sum(drive) * DT == pytest.approx(1.0, abs=1e-9)
    assert len(drive) == math.ceil(1.0 / 0.2 / DT - 1e-9)
    assert sum(turn) * DT == pytest.approx(-math.pi / 2, abs=1e-9)
    assert all(-0.5 <= w < 0 for w in turn)
    assert course.pop_events()[0] == 'drove 1.000 m open loop in 5.0 s'


def test_square_precise_ends_at_its_start():
    robot = IdealRobot(Pose2D(1.0, -2.0, 0.4))
    course = Course(legs_course(1.0, math.pi / 2, 4, 0.2, 0.7,
                                math.radians(2.0), 1.0, PRECISE))
    run(course, robot)
    dist, heading = pose_error(robot.pose, Pose2D(1.0, -2.0, 0.4))
    assert dist < 0.002
    assert abs(math.degrees(heading)) < 0.1
    assert course.ideal_end(Pose2D(1.0, -2.0, 0.4)) == pytest.approx(
        Pose2D(1.0, -2.0, 0.4))


@pytest.mark.parametrize('periods', [4, 10])  # 0.2 s and 0.5 s each way
def test_precise_mode_ends_at_its_start_over_a_slow_link(periods):
    def out_and_back(tell_age):
        robot = IdealRobot(delay=periods)
        course = Course(legs_course(1.0, math.pi, 2, 0.15, 0.5, pause=1.0,
                                    approach=PRECISE))
        run(course, robot, pose_delay=periods, tell_age=tell_age)
        dist, heading = pose_error(robot.pose, Pose2D(0.0, 0.0, 0.0))
        return dist, abs(math.degrees(heading))

    # The bound for 200 ms: 3 mm and 0.3 degrees.
    dist, heading = out_and_back(tell_age=True)
    assert dist < 0.003 and heading < 0.3
    # Steering by the old pose instead overshoots and weaves.
    dist, heading = out_and_back(tell_age=False)
    assert dist > 0.003 or heading > 0.3


class LateStops(IdealRobot):
    """An ideal robot whose stops arrive ``periods`` late (a stalled link):
    it runs on with the last move meanwhile, ``times`` times."""

    def __init__(self, periods, times=1):
        IdealRobot.__init__(self)
        self.periods, self.times = periods, times
        self.held, self.late, self.previous = 0, STOP, STOP

    def step(self, cmd, dt):
        if cmd == STOP and self.previous != STOP and self.times:
            self.held, self.times, self.late = self.periods, self.times - 1, self.previous
        self.previous = cmd
        if self.held:
            self.held -= 1
            cmd = self.late
        return IdealRobot.step(self, cmd, dt)


@pytest.mark.parametrize('step, reached', [
    (Drive(0.5, 0.2, approach=Approach(1.0, 4.0, 0.01, 0.02)), lambda r: r.x - 0.5),
    (Turn(-2.0, 1.0, approach=Approach(1.0, 4.0, 0.01, 0.02)), lambda r: -2.0 - r.yaw)])
def test_precise_mode_goes_back_when_a_late_stop_took_the_robot_past(step, reached):
    # The stop at the goal lands 0.5 s late: 5 mm (or 0.01 rad) past it at
    # creep speed. Checked on the still robot, the goal is approached again
    # from past it, to within 0.1 s of creep.
    robot = LateStops(periods=10)
    course = Course([step])
    rows = run(course, robot)
    assert abs(reached(robot)) < 0.1 * 0.02
    backs = [c for _, _, c in rows if (c.linear or c.angular) * step.goal < 0]
    assert backs and all(abs(c.linear or c.angular) <= 0.1 for c in backs)
    assert re.fullmatch(r'(drove 0\.50\d m|turned -114\.\d deg) in [\d.]+ s after 1 '
                        r'correction', course.pop_events()[0])


def test_precise_mode_gives_up_after_three_corrections_and_says_how_far_off():
    robot = LateStops(periods=20, times=10)  # every stop 1 s late
    course = Course([Drive(0.5, 0.2, approach=Approach(1.0, 4.0, 0.01, 0.02))])
    run(course, robot)
    event = course.pop_events()[0]
    # Each stop lands 1 s late, 10 mm past at creep speed; the course waits
    # for the robot to stand still (its odometry) before each check.
    assert event.endswith('after 3 corrections, still %.3f m off' % (0.5 - robot.x)), event
    assert 0.008 < abs(robot.x - 0.5) < 0.012


def test_precise_mode_checks_a_second_after_the_stop_when_odometry_never_reads_zero():
    class Jittery(IdealRobot):
        def step(self, cmd, dt):
            linear, angular = IdealRobot.step(self, cmd, dt)
            return linear + 0.001, angular  # a twist that never reads zero

    robot = Jittery()
    rows = run(Course([Drive(0.5, 0.2, approach=PRECISE)]), robot)
    moves = [i for i, (_, _, c) in enumerate(rows) if c != STOP]
    stops = len(rows) - 1 - moves[-1]  # the check waits, then the end cycle
    assert stops == pytest.approx(1.0 / DT, abs=1)
    assert robot.x == pytest.approx(0.5, abs=0.001)


def test_in_flight_adds_the_commands_sent_since_the_pose_less_the_link_delay():
    flight = InFlight()
    flight.record(10.0, Command(0.2, 0.0))
    flight.record(11.0, Command(0.0, 0.5))
    # The pose is 0.5 s old and commands take as long: those sent from
    # 11.0 to 12.0 s are still to show.
    flight.read(0.5)
    assert flight.predict(Pose2D(1.0, 2.0, 0.0), 12.0, 0.5) == pytest.approx(
        Pose2D(1.0, 2.0, 0.5))
    # A reading reused while it ages does not lengthen the command delay
    # (the smallest recent age, 0.5 s): from 10.0 s, the straight and the turn.
    flight.read(1.5)
    pose = flight.predict(Pose2D(0.0, 0.0, 0.0), 12.0, 1.5)
    assert pose == pytest.approx(Pose2D(0.2 * 1.0, 0.0, 0.5))
    assert flight.command_at(11.4) == Command(0.2, 0.0)  # sent by 10.9 s
    assert flight.command_at(11.5) == Command(0.0, 0.5)
    assert flight.command_at(9.0) == STOP
    # A fresh pose on a fast link moves on by nothing.
    fast = InFlight()
    fast.record(10.0, Command(0.2, 0.0))
    fast.read(0.0)
    assert fast.predict(Pose2D(3.0, 0.0, 1.0), 10.05, 0.0) == Pose2D(3.0, 0.0, 1.0)


def test_stalls_count_spells_of_standing_still_while_commanded_to_move():
    flight = InFlight()
    stalls = Stalls(flight, minimum=0.1)
    flight.read(0.0)
    flight.record(0.0, Command(0.2, 0.3))
    flight.record(2.0, STOP)
    spells = []
    for i in range(60):  # odometry at 50 Hz for 1.2 s, then at rest
        t = 0.02 * i
        if 0.3 <= t < 0.5 or 0.8 <= t < 0.84:  # held (0.2 s), then a blink
            measured = (0.0, 0.001)  # a tenth of the command is still
        elif 0.6 <= t < 0.7:
            measured = (0.2, 0.0)  # turning stopped, not driving: no stall
        else:
            measured = (0.19, 0.29)
        spells.append(stalls.velocity(t, *measured))
    for t in (2.1, 2.2, 2.3):  # stopped as commanded: no stall
        spells.append(stalls.velocity(t, 0.0, 0.0))
    assert [round(s, 3) for s in spells if s is not None] == [0.2]
    assert stalls.count == 1 and stalls.seconds == pytest.approx(0.2)
    # A spell still open at the end of the course counts too.
    flight.record(3.0, Command(0.1, 0.0))
    stalls.velocity(3.0, 0.0, 0.0)
    assert stalls.end(3.5) == pytest.approx(0.5) and stalls.count == 2


def test_square_book_mode_stops_each_corner_up_to_the_tolerance_short():
    robot = IdealRobot()
    course = Course(legs_course(1.0, math.pi / 2, 4, 0.2, 0.7,
                                math.radians(2.0), 1.0))
    run(course, robot)
    turns = [e for e in course.pop_events() if 'turned' in e]
    assert len(turns) == 4
    for event in turns:
        turned = float(event.split('turned ')[1].split(' deg')[0])
        # stops once turned + 2 >= 90; a 20 Hz tick turns 2.0 deg at 0.7 rad/s
        assert 88.0 - 0.05 <= turned < 88.0 + math.degrees(0.7 * DT)
    # four corners, each at most the tolerance short
    assert abs(math.degrees(pose_error(robot.pose, Pose2D(0, 0, 0))[1])) < 8.0


def test_a_move_after_a_move_is_separated_by_one_stop():
    course = Course([Turn(0.1, 1.0), Turn(0.1, 1.0)])
    robot = IdealRobot()
    rows = run(course, robot)
    commands = [c for _, _, c in rows]
    assert commands.count(STOP) == 2  # the end of each turn
    assert commands[-1] == STOP
    assert robot.yaw == pytest.approx(0.2, abs=1.0 * DT)


def test_drive_tolerance_stops_short_and_precise_ignores_it():
    for tolerance, low, high in ((0.05, 0.95, 0.95 + 0.15 * DT),
                                 (0.0, 1.0, 1.0 + 0.15 * DT)):
        robot = IdealRobot()
        run(Course([Drive(1.0, 0.15, tolerance)]), robot)
        assert low <= robot.x <= high + 1e-9
    robot = IdealRobot()
    run(Course([Drive(1.0, 0.15, 0.05, PRECISE)]), robot)
    assert robot.x == pytest.approx(1.0, abs=0.001)


def test_a_course_ending_in_a_pause_is_done_after_it():
    course = Course([Pause(0.5)])
    assert course.update(Pose2D(0, 0, 0), 0.0) == STOP and not course.done
    assert course.update(Pose2D(0, 0, 0), 0.4) == STOP and not course.done
    assert course.update(Pose2D(0, 0, 0), 0.5) == STOP and course.done
    assert course.elapsed == 0.5


def test_an_empty_course_is_refused():
    with pytest.raises(ValueError, match='at least one step'):
        Course([])


@given(yaws=st.lists(st.floats(-math.pi, math.pi), min_size=2, max_size=40))
@settings(max_examples=50, deadline=None)
def test_yaw_total_is_the_sum_of_the_wrapped_changes(yaws):
    course = Course([Pause(1000.0)])
    for k, yaw in enumerate(yaws):
        course.update(Pose2D(0.0, 0.0, yaw), float(k))
    total = sum(math.remainder(b - a, 2 * math.pi)
                for a, b in zip(yaws, yaws[1:]))
    assert course.yaw_total == pytest.approx(total, abs=1e-9)


def test_legs_params_defaults_units_and_checks():
    specs = legs_params(0.2, 1.0, 0.7, 90.0, angle_unit='deg',
                        angular_tolerance=2.0) + PRECISE_PARAMS
    values, problems = params.read_all(specs, lambda name, default: default)
    assert problems == []
    assert (values['goal_angle'], values['angular_tolerance']) == (90.0, 2.0)
    assert 'legs' not in values
    assert approach(values) is None
    assert 'goal_angle 90 deg' in params.describe(specs, values)
    assert 'precise off' in params.describe(specs, values)
    bad = {'linear_speed': 50.0, 'precise': 'maybe'}
    values, problems = params.read_all(
        specs, lambda name, default: bad.get(name, default), '~')
    assert len(problems) == 2
    assert problems[0].startswith('~linear_speed must be > 0 and <= 2')
    assert values['linear_speed'] == 0.2  # the default stands in


def test_a_tolerance_as_large_as_the_turn_is_refused():
    with pytest.raises(ValueError, match=r'angular_tolerance \(120 deg\) must '
                                         r'be smaller than the turn \(90 deg\)'):
        legs_course(0.2, math.pi / 2, 4, 0.2, 0.7, math.radians(120.0), 0.0)
    # No turn, or precise mode (which ignores the tolerance): nothing to refuse.
    legs_course(0.2, 0.0, 1, 0.2, 0.7, math.radians(120.0))
    legs_course(0.2, math.pi / 2, 1, 0.2, 0.7, math.radians(120.0),
                approach=PRECISE)


@pytest.mark.parametrize('name, value, words', [
    ('goal_distance', 1e6, r'~goal_distance must be >= -100 and <= 100'),
    ('goal_angle', 36000.0, r'~goal_angle must be >= -720 and <= 720'),
    ('angular_tolerance', 120.0, r'~angular_tolerance must be >= 0 and <= 90'),
])
def test_distances_and_angles_have_upper_bounds(name, value, words):
    specs = legs_params(0.2, 1.0, 0.7, 90.0, angle_unit='deg',
                        angular_tolerance=2.0)
    _, problems = params.read_all(
        specs, lambda n, default: value if n == name else default, '~')
    assert len(problems) == 1 and re.match(words, problems[0]), problems


def test_control_rates_show_a_missed_second():
    steady = [100.0 + 0.05 * k for k in range(201)]  # 10 s at 20 Hz
    mean, slowest = control_rates(steady)
    assert mean == pytest.approx(20.0) and slowest == 20
    late = [t for t in steady if not 103.0 <= t < 104.0] + [103.5]
    mean, slowest = control_rates(sorted(late))
    assert slowest == 1 and mean < 20.0
    assert control_rates([1.0]) == (0.0, 0)


def test_control_rates_count_ticks_on_whole_seconds_once():
    # Far from zero, 8.71 + k * 0.05 rounds some whole seconds just under.
    ticks = [8.71 + k * 0.05 for k in range(401)]
    assert control_rates(ticks)[1] == 20


class Sticky(IdealRobot):
    """An ideal robot whose wheels stick below a breakaway speed: a turn
    rate under ``angular`` rad/s (on the spot) or a speed under ``linear``
    m/s runs as a stop. It tells the velocity it ran, as odometry does."""

    def __init__(self, linear=0.02, angular=0.05, delay=0):
        IdealRobot.__init__(self, delay=delay)
        self.breakaway = (linear, angular)

    def step(self, cmd, dt):
        linear, angular = cmd
        if abs(linear) < self.breakaway[0]:
            linear = 0.0
            if abs(angular) < self.breakaway[1]:
                angular = 0.0
        return IdealRobot.step(self, Command(linear, angular), dt)


def test_precise_mode_learns_the_breakaway_speed_and_keeps_it():
    # Creep speeds 0.005 m/s and 0.01 rad/s, below where the wheels move:
    # without the breakaway the course would wait for ever at its first goal.
    robot = Sticky(delay=1)
    course = Course(legs_course(1.0, math.pi / 2, 2, 0.2, 0.5, pause=0.5,
                                approach=PRECISE))
    rows = run(course, robot, limit=200.0)
    learned = course.breakaway.speeds
    # Raised 1.5x at a time until the robot moved: at most 1.5x the breakaway.
    assert 0.02 <= learned['drive'] < 0.03 and 0.05 <= learned['turn'] < 0.075
    # Each drive and turn ends within precise mode's check, 0.1 s of its
    # creep speed (the learned one), of its goal.
    log = course.pop_events()
    drives = [float(d) for d in re.findall(r'drove ([\d.]+) m', ' '.join(log))]
    turns = [float(a) for a in re.findall(r'turned ([\d.]+) deg', ' '.join(log))]
    assert len(drives) == len(turns) == 2, log
    assert all(abs(d - 1.0) <= 0.1 * learned['drive'] + 5e-4 for d in drives), log
    assert all(abs(a - 90.0) <= math.degrees(0.1 * learned['turn']) + 0.05
               for a in turns), log
    events = [e for e in log if 'breakaway' in e]
    assert len(events) == 2, events  # one line per kind, logged once
    assert re.match(r'precise mode: the robot stood still at [\d.]+ rad/s and '
                    r'moved at 0\.0\d+ rad/s, below its breakaway speed; '
                    r'creeping at 0\.0\d+ rad/s or faster from now on \(set '
                    r'~precise_min_angular_speed', [e for e in events
                                                    if 'rad/s' in e][0])
    # The second leg creeps at the learned speeds from the start: no
    # command below them, no stall.
    leg2 = next(i for i, row in enumerate(rows) if row[1] == 'drive'
                and any(r[1] == 'turn' for r in rows[:i]))
    second = [c for _, _, c in rows[leg2:]]
    assert min(abs(c.angular) for c in second if c.angular and not c.linear) \
        >= learned['turn'] - 1e-12
    assert min(abs(c.linear) for c in second if c.linear) >= learned['drive'] - 1e-12
    # The spells the wheels stuck were the breakaway's, not a watchdog's.
    assert course.stalls.count == 0

    # A later course of the same runner starts at the learned speeds.
    again = Course([Turn(-math.pi / 2, 0.5, approach=PRECISE)], course.breakaway)
    run(again, robot, limit=100.0)
    assert not [e for e in again.pop_events() if 'breakaway' in e]
    assert again.stalls.count == 0


def test_a_stall_at_full_speed_is_left_to_the_stall_count():
    # Motors off for 2 s at the start: the robot stands still at the
    # step's own speed, which no creep speed explains.
    class MotorsOff(IdealRobot):
        def step(self, cmd, dt):
            self.t = getattr(self, 't', 0.0) + dt
            return IdealRobot.step(self, STOP if self.t <= 2.0 else cmd, dt)

    course = Course([Drive(0.5, 0.2, approach=PRECISE)])
    run(course, MotorsOff())
    assert course.breakaway.speeds == {'drive': 0.0, 'turn': 0.0}
    assert course.stalls.count == 1 and course.stalls.seconds >= 1.9
