"""The control loop's pieces (rbx1_nav.motion.runner.loop), each alone: times are
genpy's Time, as rospy's are."""
import pytest
from genpy import Time

from rbx1_nav.common.aborted import CourseAborted
from rbx1_nav.motion.runner.loop import DropoutHold, NewestTransform, FinalStops, StallCheck
from rbx1_nav.motion.course.settle import GAVE_UP, STILL, Settle
from rbx1_nav.transform_utils import Pose2D


def t(seconds):
    return Time.from_sec(seconds)


def test_a_reading_is_fresh_only_when_newer_than_the_last():
    robot = NewestTransform()
    robot.tick(t(1.0), None)
    assert not robot.fresh and robot.pose is None and robot.fresh_at == t(1.0)
    pose = Pose2D(0.1, 0.0, 0.0)
    robot.tick(t(1.05), (pose, t(1.04)))
    assert robot.fresh and robot.pose is pose and robot.fresh_at == t(1.05)
    robot.tick(t(1.1), (Pose2D(9.0, 9.0, 0.0), t(1.04)))  # the same stamp again
    assert not robot.fresh and robot.pose is pose and robot.fresh_at == t(1.05)
    assert robot.age(t(1.1)) == pytest.approx(0.06, abs=1e-9)


class Log(object):
    def __init__(self):
        self.lines = []

    def __call__(self, text):
        self.lines.append(text)


def test_the_hold_holds_a_stale_transform_then_gives_up_robot_stopped():
    warn, info, stops = Log(), Log(), []
    hold = DropoutHold('course', 'tf odom -> base_footprint', 1.0, 2.0,
                lambda: stops.append(1), warn, info)
    robot = NewestTransform()
    robot.tick(t(0.0), (Pose2D(0.0, 0.0, 0.0), t(0.0)))
    assert not hold.held(t(0.5), robot)
    assert hold.held(t(1.5), robot)  # 1.5 s old: past ~tf_timeout
    assert len(warn.lines) == 1 and 'not been updated for 1.50 s' in warn.lines[0]
    assert hold.held(t(2.5), robot) and len(warn.lines) == 1  # said once
    robot.tick(t(2.6), (Pose2D(0.0, 0.0, 0.0), t(2.6)))
    assert not hold.held(t(2.6), robot)
    assert info.lines == ['course: tf odom -> base_footprint is back after 2.60 s; '
                          'carrying on from where it says the robot is']
    assert hold.summary() == '1 time, 2.6 s in all'
    with pytest.raises(CourseAborted, match=r'not been updated for 3\.10 s'):
        hold.held(t(5.7), robot)  # 3.1 s: past ~tf_timeout + ~link_grace
    assert stops == [1]


def test_the_hold_names_a_transform_arriving_stamped_long_ago():
    warn = Log()
    hold = DropoutHold('course', 'tf', 1.0, 2.0, lambda: None, warn, Log())
    robot = NewestTransform()
    robot.tick(t(10.0), (Pose2D(0.0, 0.0, 0.0), t(8.5)))
    assert hold.held(t(10.0), robot)
    assert 'is 1.50 s old by its stamp though still arriving' in warn.lines[0]


class Stalls(object):
    def __init__(self, spells):
        self.spells = list(spells)
        self.fed = []

    def velocity(self, stamp, linear, angular):
        self.fed.append((stamp, linear, angular))
        return self.spells.pop(0)


class Course(object):
    def __init__(self, spells):
        self.stalls = Stalls(spells)


def test_the_stall_check_feeds_seconds_from_the_first_tick_and_says_each_spell():
    warn = Log()
    course = Course([None, 0.25])
    StallCheck('course', warn).check(course, t(100.0), iter([(t(100.5), 0.2, 0.0),
                                                             (t(101.0), 0.0, 0.0)]))
    assert course.stalls.fed == [(0.5, 0.2, 0.0), (1.0, 0.0, 0.0)]
    assert len(warn.lines) == 1
    assert warn.lines[0].startswith('course: the robot stood still for 0.25 s while '
                                    'commanded to move')


def test_settling_waits_for_the_stops_to_be_delivered_then_for_a_still_robot():
    end = Pose2D(1.0, 0.0, 0.0)
    settling = FinalStops(Settle(end, 10.0, 0.5, 3.0), message_bytes=52)
    robot = NewestTransform()
    robot.tick(t(10.1), (end, t(10.1)))
    # Two stops sent, 200 bytes unacknowledged: a command from before
    # the end is still on its way, so no still spell begins.
    assert not settling.done(False, robot, t(0.0), 200)
    assert settling.settle.undelivered == pytest.approx(10.1)
    robot.tick(t(10.2), (end, t(10.2)))
    assert not settling.done(False, robot, t(0.0), 0)  # still since 10.2 s
    robot.tick(t(10.5), (end, t(10.5)))
    assert not settling.done(True, robot, t(0.0), 0)  # held: the wait pauses
    assert not settling.done(False, robot, t(0.0), 0)  # not fresh
    robot.tick(t(10.7), (end, t(10.7)))
    assert settling.done(False, robot, t(0.0), 0)
    assert settling.settle.state == STILL and not settling.waiting
    assert settling.stops == 5


def test_settling_gives_up_on_a_robot_still_moving():
    settling = FinalStops(Settle(Pose2D(0.0, 0.0, 0.0), 0.0, 0.5, 1.0), message_bytes=52)
    robot = NewestTransform()
    done = False
    for k in range(1, 30):
        robot.tick(t(0.1 * k), (Pose2D(0.01 * k, 0.0, 0.0), t(0.1 * k)))
        done = settling.done(False, robot, t(0.0), None)
        if done:
            break
    assert done and settling.settle.state == GAVE_UP and k == 10
