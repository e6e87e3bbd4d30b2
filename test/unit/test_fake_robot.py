"""Unit tests for rbx1_nav.fake_robot: the fake robot's shared parameters
and the per-robot warning throttle (no master)."""
from rbx1_nav import fake_robot
from rbx1_nav.diff_drive import DiffDriveConfig
from rbx1_nav.params import read_all


def test_every_model_setting_is_a_parameter():
    names = [spec.name for spec in fake_robot.PARAMS]
    assert set(DiffDriveConfig.names()) <= set(names)
    assert len(names) == len(set(names))
    assert 'robots' not in names  # fake_fleet's own


def test_robots_parameter_reads_a_list_of_namespaces():
    values, problems = read_all((fake_robot.ROBOTS,),
                                lambda name, default: ['robot1', '/robot2'], '~')
    assert (values['robots'], problems) == (['robot1', 'robot2'], [])
    values, problems = read_all((fake_robot.ROBOTS,),
                                lambda name, default: ['r'] * 2, '~')
    assert problems == ["~robots names 'r' twice"]
    values, problems = read_all(
        (fake_robot.ROBOTS,),
        lambda name, default: ['r%d' % k for k in range(fake_robot.MAX_ROBOTS + 1)], '~')
    assert 'at most %d names' % fake_robot.MAX_ROBOTS in problems[0]


def test_throttle_repeats_a_warning_once_per_period_per_key():
    throttle = fake_robot.Throttle(period=5.0)
    assert throttle.ready(('robot1', 'clamped'), 10.0)
    assert not throttle.ready(('robot1', 'clamped'), 12.0)
    # Another robot or another warning is not held back by the first.
    assert throttle.ready(('robot2', 'clamped'), 12.0)
    assert throttle.ready(('robot1', 'non-finite'), 12.0)
    assert not throttle.ready(('robot1', 'clamped'), 15.0)
    assert throttle.ready(('robot1', 'clamped'), 15.01)


def test_throttle_allows_the_warning_again_when_time_moves_backwards():
    throttle = fake_robot.Throttle(period=5.0)
    assert throttle.ready('clamped', 100.0)
    assert throttle.ready('clamped', 3.0)  # a restarted simulation clock
    assert not throttle.ready('clamped', 4.0)
