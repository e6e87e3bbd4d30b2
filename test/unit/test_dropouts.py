"""rbx1_nav.motion.runner.loop.Dropouts: a stale transform is held, ridden out, or given up."""
import pytest

from rbx1_nav.motion.runner.loop import FRESH, HOLD, LOST, Dropouts
from rbx1_nav.motion.course.command import STOP
from rbx1_nav.motion.course.course import Course
from rbx1_nav.motion.course.steps import Drive
from rbx1_nav.transform_utils import Pose2D


def run(dropouts, fresh_times, end, dt=0.05):
    """Tick every ``dt`` s to ``end``; the transform updates at the ticks
    nearest ``fresh_times``. Returns the ticks."""
    ticks, fresh_at, now = [], 0.0, 0.0
    fresh = sorted(fresh_times)
    while now <= end + 1e-9:
        if fresh and fresh[0] <= now + 1e-9:
            fresh_at = now
            while fresh and fresh[0] <= now + 1e-9:
                fresh.pop(0)
        ticks.append((now, dropouts.tick(now, fresh_at)))
        now = round(now + dt, 9)
    return ticks


def test_a_fresh_transform_is_never_held():
    d = Dropouts(timeout=1.0, grace=3.0)
    ticks = run(d, [0.05 * k for k in range(100)], 4.9)
    assert all(t.state == FRESH and not t.began and t.ended is None for _, t in ticks)
    assert d.count == 0 and d.summary() == 'never'


def test_a_dropout_within_the_grace_is_held_then_ridden_out():
    d = Dropouts(timeout=1.0, grace=3.0)
    # Fresh every tick to 1.0 s, silent to 3.0 s, fresh again after.
    fresh = [0.05 * k for k in range(21)] + [3.0 + 0.05 * k for k in range(20)]
    ticks = run(d, fresh, 4.0)
    states = {now: t for now, t in ticks}
    assert states[1.95].state == FRESH  # 0.95 s old: within ~tf_timeout
    assert states[2.05].state == HOLD and states[2.05].began
    assert sum(t.began for _, t in ticks) == 1
    assert all(t.state == HOLD for now, t in ticks if 2.0 < now < 3.0)
    assert states[3.0].state == FRESH
    assert states[3.0].ended == pytest.approx(2.0)  # last fresh at 1.0 s
    assert d.count == 1 and d.seconds == pytest.approx(2.0)
    assert d.summary() == '1 time, 2.0 s in all'


def test_past_the_grace_the_course_is_lost():
    d = Dropouts(timeout=1.0, grace=0.5)
    ticks = run(d, [0.0], 3.0)
    lost = [now for now, t in ticks if t.state == LOST]
    assert lost and lost[0] == pytest.approx(1.55)  # stale 1.55 > 1.0 + 0.5
    assert all(t.state == HOLD for now, t in ticks if 1.0 < now <= 1.5)
    assert d.count == 0


def test_no_grace_gives_up_at_the_timeout_without_holding():
    d = Dropouts(timeout=1.0, grace=0.0)
    ticks = run(d, [0.0], 2.0)
    assert not any(t.state == HOLD for _, t in ticks)
    assert [now for now, t in ticks if t.state == LOST][0] == pytest.approx(1.05)


def test_two_dropouts_are_counted_apart():
    d = Dropouts(timeout=0.5, grace=2.0)
    fresh = ([0.1 * k for k in range(11)] + [2.0 + 0.1 * k for k in range(11)]
             + [4.0 + 0.1 * k for k in range(11)])
    run(d, fresh, 5.0, dt=0.1)
    assert d.count == 2 and d.seconds == pytest.approx(2.0)
    assert d.summary() == '2 times, 2.0 s in all'


@pytest.mark.parametrize('timeout, grace', [(0.0, 1.0), (-1.0, 1.0), (1.0, -0.1)])
def test_bad_limits_are_refused(timeout, grace):
    with pytest.raises(ValueError):
        Dropouts(timeout, grace)


def test_a_held_course_records_the_stop_and_goes_on_from_the_new_pose():

    course = Course([Drive(1.0, 0.2)])
    assert course.update(Pose2D(0.0, 0.0, 0.0), 0.0).linear == pytest.approx(0.2)
    assert course.hold(0.5) == STOP
    assert course.context.in_flight.command_at(0.6) == STOP  # held, not still driving
    # Back: the robot is where tf says, and the drive goes on to its goal.
    assert course.update(Pose2D(0.5, 0.0, 0.0), 1.0).linear == pytest.approx(0.2)
    course.update(Pose2D(1.0, 0.0, 0.0), 1.1)
    assert course.done


def test_a_transform_arriving_but_stamped_long_ago_is_held():
    """A link that holds messages back delivers them late: the age counts
    from the stamp when that is earlier than the arrival."""
    d = Dropouts(timeout=1.0, grace=0.5)
    assert d.tick(5.0, fresh_at=5.0, stamp=4.1).state == FRESH  # 0.9 s old
    held = d.tick(5.1, fresh_at=5.1, stamp=4.05)  # a late one: 1.05 s old
    assert held.state == HOLD and held.began and held.stale == pytest.approx(1.05)
    back = d.tick(5.2, fresh_at=5.2, stamp=5.15)
    assert back.state == FRESH and back.ended == pytest.approx(5.2 - 4.05)
    assert d.tick(7.0, fresh_at=7.0, stamp=5.4).state == LOST  # 1.6 s > 1.0 + 0.5


def test_a_stamp_later_than_the_arrival_counts_from_the_arrival():
    """A robot's clock ahead of this one's stamps the future: the arrival
    still counts (the link cut shows as before)."""
    d = Dropouts(timeout=1.0, grace=0.5)
    assert d.tick(5.0, fresh_at=3.9, stamp=4.5).state == HOLD  # not updated 1.1 s
