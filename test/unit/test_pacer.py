"""Unit tests for rbx1_nav.sim_time.pacer.ClockPacer, with a fake wall clock."""
import pytest

from rbx1_nav.sim_time import pacer
from rbx1_nav.sim_time.pacer import ClockPacer


def run(pacer, ticks, wall=100.0, extra_delay=0.0):
    """Follow the pacer like the node does; return (sim ns list, wall end)."""
    sims = []
    for _ in range(ticks):
        sim_ns, wait = pacer.advance(wall)
        wall += wait + extra_delay
        sims.append(sim_ns)
    return sims, wall


@pytest.mark.parametrize('speed', [0.5, 1.0, 20.0])
def test_sim_time_runs_at_speed_in_exact_steps(speed):
    pacer = ClockPacer(speed, step=0.01, start=2.0)
    sims, wall_end = run(pacer, 1000)
    assert sims[0] == 2_010_000_000
    assert set(b - a for a, b in zip(sims, sims[1:])) == {10_000_000}
    sim_elapsed = (sims[-1] - 2_000_000_000) * 1e-9
    assert sim_elapsed / (wall_end - 100.0) == pytest.approx(speed, rel=1e-6)


def test_falling_behind_slows_the_clock_instead_of_bursting():
    pacer = ClockPacer(20.0, step=0.01)
    # Each publish costs 5 ms of wall time, ten times the 0.5 ms budget.
    sims, wall_end = run(pacer, 200, extra_delay=0.005)
    assert set(b - a for a, b in zip(sims, sims[1:])) == {10_000_000}
    assert sims[-1] * 1e-9 / (wall_end - 100.0) == pytest.approx(2.0, rel=0.01)
    # After a long stall it re-anchors: no burst, then one step per 0.5 ms.
    assert pacer.advance(wall_end + 1.0)[1] == 0.0
    assert pacer.advance(wall_end + 1.0)[1] == pytest.approx(0.0005)


@pytest.mark.parametrize('args', [(0.0,), (float('inf'),), (-1.0,), (1.0, 0.02),
                                  (1.0, 0.0), (1.0, 0.01, -5.0), (float('nan'),),
                                  (1e-300,), (1e300,), (1.0, float('nan')),
                                  (1.0, 1e-300), (1.0, 0.01, float('nan')),
                                  (1.0, 0.01, 1e308)])
def test_invalid_settings_are_rejected(args):
    with pytest.raises(ValueError):
        ClockPacer(*args)


def test_extreme_but_valid_settings_give_sane_waits():
    for speed, step, start in ((1e-3, 0.01, 0.0), (1e6, 1e-9, 2.0 ** 31)):
        pacer = ClockPacer(speed, step, start)
        sim_ns, wait = pacer.advance(100.0)
        assert sim_ns == int(round(start * 1e9)) + int(round(step * 1e9))
        assert wait == pytest.approx(step / speed)


def test_max_speed_never_waits_and_keeps_exact_steps():
    pacer = ClockPacer(None, step=0.01)
    sims, wall_end = run(pacer, 100)
    assert wall_end == 100.0
    assert sims[-1] == 1_000_000_000


def test_a_new_speed_takes_over_from_the_next_step():
    pacer = ClockPacer(None, step=0.01)
    run(pacer, 10)
    pacer.set_speed(1.0)
    sims, wall_end = run(pacer, 100, wall=50.0)
    assert wall_end - 50.0 == pytest.approx(1.0)


@pytest.mark.parametrize('value, expected', [('max', None), (' MAX ', None),
                                             (10, 10.0), ('2.5', 2.5)])
def test_speed_parameter(value, expected):
    assert pacer.speed("~speed", value) == expected


@pytest.mark.parametrize('value', ['fast', 0, -1, float('nan'), 1e9, True])
def test_bad_speed_parameter_names_max(value):
    with pytest.raises(ValueError, match="'max' or a number"):
        pacer.speed("~speed", value)


def test_a_granted_step_is_reached_in_one_jump():
    pacer = ClockPacer(1.0, step=0.01)
    assert pacer.advance(0.0, target=3_333_333) == (3_333_333, pytest.approx(0.003333333))
    # Event-driven: 50 ms on in one go, paced at real time.
    sim_ns, wait = pacer.advance(0.003333333, target=53_333_333)
    assert sim_ns == 53_333_333 and wait == pytest.approx(0.05)
    assert pacer.advance(0.053333333)[0] == 63_333_333


def test_a_target_in_the_past_is_refused():
    pacer = ClockPacer(None, step=0.01, start=1.0)
    with pytest.raises(ValueError, match='not after'):
        pacer.advance(0.0, target=1_000_000_000)
    assert pacer.sim_ns == 1_000_000_000


def test_the_start_up_line_says_max_for_a_speed_of_max():
    # params.describe showed 'speed None x real time' for sim_speed:=max.
    from rbx1_nav.common.params import describe, param
    specs = [param('speed', 1.0, pacer.speed, 'x real time'),
             param('seed', None, lambda name, value: value)]
    values = {'speed': pacer.speed('speed', 'max'), 'seed': None}
    assert describe(specs, values) == 'speed max x real time, seed none'
