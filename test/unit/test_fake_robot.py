"""Unit tests for rbx1_nav.fake_robot: the fake robot's shared parameters
(no master)."""
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
