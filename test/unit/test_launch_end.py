"""Unit tests for rbx1_nav.common.launch_end: when a wrapped node's clean exit
ends its roslaunch (nodes/end_launch_on_success.py)."""
import os

from rbx1_nav.common.launch_end import is_roslaunch, node_name, others_running, processes, run

ROSLAUNCH = ['/usr/bin/python3', '/usr/bin/roslaunch', 'rbx1_nav', 'nav_square.launch']
WRAPPER = ['/usr/bin/python3', '/ws/devel/lib/rbx1_nav/end_launch_on_success.py']


def test_only_roslaunch_itself_is_ended():
    assert is_roslaunch(ROSLAUNCH)
    assert is_roslaunch(['roslaunch', '-p', '11311', 'x.launch'])
    assert not is_roslaunch(['/usr/bin/python3', '/usr/bin/rostest', 'nav_square.test'])
    assert not is_roslaunch(['/usr/bin/python3', '/usr/bin/roslaunch', '--child',
                             '--server_uri=http://h:1/', '--run_id=x'])
    assert not is_roslaunch(['bash'])


def test_the_last_wrapped_node_of_a_launch_ends_it():
    procs = {10: (1, ROSLAUNCH),
             20: (10, WRAPPER + ['/n/odom_out_and_back.py']),
             30: (10, WRAPPER + ['/n/odom_out_and_back.py']),
             31: (30, ['/usr/bin/python3', '/n/odom_out_and_back.py']),
             40: (10, ['/usr/bin/python3', '/n/fake_fleet.py'])}
    assert others_running(20, procs)  # 30's course still drives
    del procs[31]
    assert not others_running(20, procs)
    assert not others_running(20, {10: (1, ROSLAUNCH), 20: (10, WRAPPER)})
    # A wrapper of another launch does not count.
    assert not others_running(20, {20: (10, WRAPPER), 50: (11, WRAPPER), 51: (50, ['x'])})


def test_processes_reads_this_process_and_its_parent():
    procs = processes()
    assert procs[os.getpid()][0] == os.getppid()
    assert procs[os.getpid()][1]


def test_node_name_as_roslaunch_shows_it():
    args = ['/n/odom_out_and_back.py', '__name:=odom_out_and_back', '__log:=/x.log']
    assert node_name(args, '/robot2') == 'robot2/odom_out_and_back'
    assert node_name(args) == 'odom_out_and_back'
    assert node_name(['/n/nav_square.py']) == 'nav_square.py'


def test_the_wrapper_passes_the_nodes_status_and_leaves_a_non_roslaunch_parent_alone(capsys):
    """Under pytest (no roslaunch parent) a node's status is the wrapper's."""
    assert run(['true'], 'doc') == 0
    assert run(['false'], 'doc') == 1
    assert run([], 'the doc\n') == 2
    assert capsys.readouterr().out == 'the doc\n'


def test_statuses_recorded_are_read_back_in_order(tmp_path):
    from rbx1_nav.common.launch_end import read_statuses, record_status
    record_status(str(tmp_path), 'robot1/odom_out_and_back', 0)
    assert read_statuses(str(tmp_path)) == [(0, 'robot1/odom_out_and_back')]
    (tmp_path / 'junk.status').write_text('not a status')
    assert read_statuses(str(tmp_path)) == [(0, 'robot1/odom_out_and_back')]


def test_the_launch_status_is_the_first_failed_course_else_roslaunchs():
    from rbx1_nav.common.launch_end import launch_status
    assert launch_status([(0, 'nav_square')], 0) == (
        0, 'launch_status: nav_square exited 0')
    status, line = launch_status([(0, 'robot1/c'), (1, 'robot2/c'), (130, 'robot3/c')], 0)
    assert status == 1 and line == 'launch_status: robot2/c exited 1; exiting 1'
    assert launch_status([], 1)[0] == 1
    assert launch_status([], 0) == (0, 'launch_status: roslaunch exited 0 '
                                       '(no course in the launch)')


def test_forget_is_called_only_under_roslaunch():
    forgotten = []
    assert run(['true'], 'doc', forget=forgotten.append) == 0
    assert forgotten == []  # pytest is not roslaunch


def test_launch_status_without_arguments_prints_its_help(capsys):
    from rbx1_nav.common.launch_end import run_launch
    assert run_launch([], 'the doc\n') == 2
    assert capsys.readouterr().out == 'the doc\n'


def test_a_launchs_clock_clears_its_simulated_time_unless_another_clock_runs():
    from rbx1_nav.common.launch_end import sim_time_to_clear
    assert sim_time_to_clear(True, []) == ('/use_sim_time', '/lockstep')
    # A bag played with --clock, or a sim_clock started by hand, still
    # serves nodes that read /use_sim_time as they start.
    assert sim_time_to_clear(True, ['/play_bag']) == ()
    # A clock the user started (rosrun sim_clock.py): the user set them.
    assert sim_time_to_clear(False, []) == ()


def test_the_wrappers_clock_is_a_node_that_publishes_clock():
    from rbx1_nav.common.launch_end import publishes_clock
    assert publishes_clock(['/opt/ros/lib/rosbag/play', '--clock', '--delay=2', 'c.bag'])
    assert not publishes_clock(['/opt/ros/lib/rosbag/play', 'c.bag'])
    assert not publishes_clock(['--clock'])


def test_the_parent_is_roslaunch_only_under_roslaunch(tmp_path):
    from rbx1_nav.common.launch_end import parent_is_roslaunch
    assert not parent_is_roslaunch()  # pytest's parent
    proc = tmp_path / str(os.getppid())
    proc.mkdir()
    (proc / 'cmdline').write_bytes(b'\0'.join(arg.encode() for arg in ROSLAUNCH) + b'\0')
    assert parent_is_roslaunch(str(tmp_path))
    assert not parent_is_roslaunch(str(tmp_path / 'none'))


def test_end_clock_is_called_only_under_roslaunch():
    ended = []
    assert run(['true', '--clock'], 'doc', end_clock=lambda: ended.append(1)) == 0
    assert ended == []  # pytest is not roslaunch
