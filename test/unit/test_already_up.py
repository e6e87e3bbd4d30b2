"""rbx1_nav.common.already_up: the name a node would register, and the lines
of a second robot refused."""
from rbx1_nav.common.already_up import refusal_text, resolved_name, skip_text


def test_resolved_name_from_default_namespace_and_remaps():
    assert resolved_name(['fake_turtlebot.py'], '', 'fake_turtlebot') == '/fake_turtlebot'
    assert resolved_name(['x', '__name:=rsp', '__log:=/tmp/l'], '/robot1/',
                         'robot_state_publisher') == '/robot1/rsp'
    assert resolved_name(['x', '__ns:=/a/b'], '/robot1', 'sim_clock') == '/a/b/sim_clock'


def test_refusal_names_the_robot_and_both_ways_on():
    line = refusal_text('/robot1/fake_turtlebot', 4242)
    assert 'already running as /robot1/fake_turtlebot (pid 4242' in line
    assert 'without sim:=true' in line and 'nav_square.launch' in line
    assert 'rosnode kill /robot1/fake_turtlebot' in line


def test_skip_names_the_node_and_why():
    line = skip_text('/sim_clock', 7)
    assert line.startswith('/sim_clock is already running (pid 7)')
    assert 'shut it down' in line
