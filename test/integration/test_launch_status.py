"""A launch's end, as a script sees it.

launch_status.py exits with the course's status (roslaunch exits 0 even
when a required course failed), and a course's launch leaves none of its
parameters behind: a plain rosrun afterwards runs with its defaults (a
launch with sim_speed:=5 record:=true once left start_delay 10 s and
tf_wait 25 s, and the next rosrun waited 10 s before moving). The courses
here run under lockstep simulated time (rbx1_nav.common.launch_end)."""
import os
import signal
import sys

import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import test_second_robot  # noqa: E402

Graph = test_second_robot.Graph
pytestmark = test_second_robot.pytestmark

HANG_GUARD = test_second_robot.HANG_GUARD


@pytest.fixture
def graph(tmp_path):
    g = Graph(tmp_path)
    yield g
    g.close()


def launch_status(graph, *args):
    return graph.run(['rosrun', 'rbx1_nav', 'launch_status.py', 'rbx1_nav'] + list(args),
                     timeout=HANG_GUARD)


def course_logs(log_dir, node):
    """Every log file of ``node`` under ``log_dir``, joined."""
    text = []
    for path in sorted(log_dir.rglob('*%s*.log' % node)):
        text.append(path.read_text(errors='replace'))
    return '\n'.join(text)


def test_launch_status_exits_with_the_courses_status(graph, tmp_path):
    done = launch_status(graph, 'nav_square.launch', 'sim:=true', 'sim_speed:=max')
    assert done.returncode == 0, done.stdout[-4000:]
    assert 'Course complete' in done.stdout
    assert done.stdout.rstrip().endswith('launch_status: nav_square exited 0'), done.stdout[-2000:]

    # No robot: the course gives up after ~tf_wait (5 wall s) and exits 1;
    # roslaunch alone would exit 0. Real time, as a user with no robot has
    # it: the launch above left /use_sim_time true (the course would give up
    # for want of /clock instead).
    graph.run(['rosparam', 'set', '/use_sim_time', 'false'])
    failed = launch_status(graph, 'odom_out_and_back.launch')
    assert failed.returncode == 1, failed.stdout[-4000:]
    # The course's own reason, not any failure (a traceback exits 1 too),
    # in its log (ROS_LOG_DIR is the test's own tmp_path).
    logs = course_logs(tmp_path, 'odom_out_and_back')
    assert 'no transform from odom to base_footprint or base_link' in logs, logs[-4000:]
    assert 'Traceback' not in logs, logs[-4000:]
    assert failed.stdout.rstrip().endswith(
        'launch_status: odom_out_and_back exited 1; exiting 1'), failed.stdout[-2000:]
    plain = graph.run(['roslaunch', 'rbx1_nav', 'odom_out_and_back.launch'],
                      timeout=HANG_GUARD)
    assert plain.returncode == 0 and 'REQUIRED process' in plain.stdout  # why it exists


def test_a_later_rosrun_runs_with_its_defaults(graph, tmp_path):
    done = launch_status(graph, 'odom_out_and_back_sim.launch', 'sim_speed:=5',
                         'record:=true', 'bag:=%s' % (tmp_path / 'course.bag'))
    assert done.returncode == 0, done.stdout[-4000:]
    assert 'start_delay 10 s' in done.stdout  # the launch did set it
    names = graph.run(['rosparam', 'list']).stdout.split()
    assert not [n for n in names if n.startswith('/odom_out_and_back/')], names

    robot = graph.start(['roslaunch', 'rbx1_nav', 'fake_turtlebot.launch'], 'robot')
    graph.wait_for(lambda: '/fake_turtlebot' in graph.nodes(), 'robot', robot, 'robot')
    course = graph.start(['rosrun', 'rbx1_nav', 'odom_out_and_back.py'], 'course')
    graph.wait_for(lambda: 'leg 1' in graph.output('course'), 'the course under way',
                   course, 'course')
    os.killpg(course.pid, signal.SIGINT)
    course.wait(HANG_GUARD)
    out = graph.output('course')
    print(out)
    assert 'leg 1' in out, out
    assert 'odom_out_and_back: every parameter at its default' in out, out
    assert 'Starting in' not in out and 'from the parameter server' not in out, out
