"""Unit tests for rbx1_nav.sim.params: the fake robot's shared parameters
(no master)."""
from rbx1_nav.sim import params as sim_params
from rbx1_nav.sim.diff_drive import DiffDriveConfig
from rbx1_nav.common.params import read_all


def test_every_model_setting_is_a_parameter():
    names = [spec.name for spec in sim_params.PARAMS]
    assert set(DiffDriveConfig.names()) <= set(names)
    assert len(names) == len(set(names))
    assert 'robots' not in names  # fake_fleet's own


def test_robots_parameter_reads_a_list_of_namespaces():
    values, problems = read_all((sim_params.ROBOTS,),
                                lambda name, default: ['robot1', '/robot2'], '~')
    assert (values['robots'], problems) == (['robot1', 'robot2'], [])
    values, problems = read_all((sim_params.ROBOTS,),
                                lambda name, default: ['r'] * 2, '~')
    assert problems == ["~robots names 'r' twice"]
    values, problems = read_all(
        (sim_params.ROBOTS,),
        lambda name, default: ['r%d' % k for k in range(sim_params.MAX_ROBOTS + 1)], '~')
    assert 'at most %d names' % sim_params.MAX_ROBOTS in problems[0]
