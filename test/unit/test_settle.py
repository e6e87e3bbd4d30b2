"""rbx1_nav.motion.course.settle: after a course, wait for a still robot and take its pose."""
import math

import pytest

from rbx1_nav.motion.course.settle import (ANGULAR_EPS, GAVE_UP, LINEAR_EPS, STILL,
                                    WAITING, Settle, delivered, moved_text)
from rbx1_nav.transform_utils import Pose2D

DT = 0.05  # s, the control period of the ticks below
END = Pose2D(1.0, 2.0, 0.5)
WATCHDOG = 0.5  # s, the fake robot's cmd_timeout


def run(settle, pose_at, lag=0.0, limit=20.0, sent_at=0.0):
    """Feed ``settle`` one pose a tick from its end on: ``pose_at(stamp)``
    read ``lag`` s late, every command sent before the end delivered from
    ``sent_at`` s after it. Returns (state, time now) at the first tick
    that is not WAITING."""
    now = settle.ended
    while now < settle.ended + limit:
        now += DT
        stamp = now - lag
        state = settle.update(pose_at(stamp), stamp,
                              now >= settle.ended + sent_at - 1e-9)
        if state != WAITING:
            return state, now
    raise AssertionError('still waiting after %g s' % limit)


def test_a_still_robot_settles_after_settle_time_and_did_not_move():
    settle = Settle(END, 10.0, 0.6, 5.0)
    state, now = run(settle, lambda t: END)
    assert state == STILL
    assert now == pytest.approx(10.6)
    assert settle.pose == END
    assert settle.moved() == (0.0, 0.0)
    assert moved_text(settle.moved()) is None
    assert settle.undelivered is None


def test_a_late_command_shows_and_the_settled_pose_is_where_it_stopped():
    """A creep turn (0.02 rad/s) lands 0.3 s after the end and runs until the
    robot's watchdog stops it 0.5 s later: stillness counts from then."""
    def pose_at(t):
        turned = 0.02 * min(max(t - 10.3, 0.0), WATCHDOG)
        return Pose2D(END.x, END.y, END.yaw + turned)
    settle = Settle(END, 10.0, 0.6, 5.0)
    state, now = run(settle, pose_at)
    assert state == STILL
    assert now == pytest.approx(10.8 + 0.6, abs=DT + 1e-9)
    assert settle.pose.yaw - END.yaw == pytest.approx(0.01)
    moved = settle.moved()
    assert moved.distance == 0.0 and moved.yaw == pytest.approx(0.01)
    text = moved_text(moved)
    assert '0.0 mm / +0.57 deg after the course ended (a late command?)' in text


def test_a_command_held_back_by_the_link_is_waited_for():
    """TCP holds a creep command (and the stops after it) for 3 s behind a
    lost packet: the still spell begins once the robot's host has them all,
    and the creep it ran meanwhile (until the stop behind it) shows."""
    def pose_at(t):
        return Pose2D(END.x, END.y, END.yaw + (0.003 if t >= 13.0 else 0.0))
    settle = Settle(END, 10.0, 0.6, 5.0)
    state, now = run(settle, pose_at, sent_at=3.0)
    assert state == STILL
    assert now == pytest.approx(13.6)
    assert settle.moved().yaw == pytest.approx(0.003)
    assert settle.undelivered == pytest.approx(12.95)
    # Never delivered within the timeout: it gives up, and says why.
    stuck = Settle(END, 10.0, 0.6, 5.0)
    state, now = run(stuck, lambda t: END, sent_at=99.0)
    assert state == GAVE_UP and not stuck.sent
    assert now == pytest.approx(15.0)


def test_delivered_when_only_the_commands_after_the_end_are_unacknowledged():
    assert delivered(0, 0, 52)
    assert delivered(104, 2, 52)
    assert not delivered(105, 2, 52)
    assert not delivered(52, 0, 52)
    assert delivered(None, 0, 52)  # cannot tell: not held up


def test_stillness_counts_odometry_stamps_after_the_end_only():
    """A transform 0.2 s old: 0.6 s of still stamps after the end take
    0.8 s of the clock."""
    settle = Settle(END, 10.0, 0.6, 5.0)
    state, now = run(settle, lambda t: END, lag=0.2)
    assert state == STILL
    assert now == pytest.approx(10.8)


def test_rounding_noise_is_still_but_slow_drift_is_not():
    jitter = Settle(END, 0.0, 0.6, 5.0)
    state, _ = run(jitter, lambda t: Pose2D(
        END.x + 0.5 * LINEAR_EPS * math.sin(50 * t), END.y,
        END.yaw + 0.5 * ANGULAR_EPS * math.cos(50 * t)))
    assert state == STILL
    # Creeping 0.1 mm/s: each tick's step is under LINEAR_EPS, the spell's
    # change is not.
    drift = Settle(END, 0.0, 0.6, 5.0)
    state, now = run(drift, lambda t: Pose2D(END.x + 1e-4 * t, END.y, END.yaw))
    assert state == GAVE_UP
    assert now == pytest.approx(5.0)
    assert moved_text(drift.moved()).startswith('the robot moved 0.5 mm / +0.00 deg')


def test_a_robot_that_keeps_moving_gives_up_at_the_timeout():
    settle = Settle(END, 3.0, 0.6, 2.0)
    state, now = run(settle, lambda t: Pose2D(END.x + 0.01 * t, END.y, END.yaw))
    assert state == GAVE_UP
    assert now == pytest.approx(5.0)


def test_the_timeout_counts_odometry_stamps_not_the_clock():
    """Poses read 1 s late (a slow link): it gives up on odometry stamped
    2 s after the end, 3 s of the clock; a stale transform is the runner's
    dropout hold to judge."""
    settle = Settle(END, 3.0, 0.6, 2.0)
    state, now = run(settle, lambda t: Pose2D(END.x + 0.01 * t, END.y, END.yaw),
                     lag=1.0)
    assert state == GAVE_UP
    assert now == pytest.approx(6.0)


def test_moved_wraps_the_yaw_and_words_only_what_counts():
    end = Pose2D(0.0, 0.0, math.pi - 0.001)
    settle = Settle(end, 0.0, 0.6, 5.0)
    settle.update(Pose2D(0.0003, 0.0004, -math.pi + 0.001), 0.1)
    moved = settle.moved()
    assert moved.distance == pytest.approx(0.0005)
    assert moved.yaw == pytest.approx(0.002)
    assert moved_text(moved) == ('the robot moved 0.5 mm / +0.11 deg after the '
                                 'course ended (a late command?)')
    # Within 0.1 mm and 0.01 deg: nothing to say.
    small = Settle(END, 0.0, 0.6, 5.0)
    small.update(Pose2D(END.x + 0.00009, END.y, END.yaw - math.radians(0.009)), 0.1)
    assert moved_text(small.moved()) is None


@pytest.mark.parametrize('settle_time, timeout', [(0.0, 5.0), (0.6, 0.0), (-1.0, 5.0)])
def test_bad_times_are_refused(settle_time, timeout):
    with pytest.raises(ValueError):
        Settle(END, 0.0, settle_time, timeout)
