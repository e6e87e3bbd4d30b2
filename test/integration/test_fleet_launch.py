"""fleet.launch starts what it says, for any n (checked with what roslaunch's
--nodes, --args and --dump-params print, which parse without starting
anything, read in this process: test/helpers/launch_reading.py):
one fake_fleet.py with robot1 .. robotN or one fake_turtlebot.py per robot,
and with course:=true one course per robot, each with its robot's frames
and its tf remapped to the robot's own topics; the last course to succeed
ends the launch unless end:=false."""
import os
import shutil
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'helpers'))
from launch_reading import node_command, nodes, params  # noqa: E402

pytestmark = pytest.mark.skipif(
    not shutil.which('roslaunch') or 'ROS_PACKAGE_PATH' not in os.environ,
    reason='needs a sourced ROS workspace (make test sources one)')


@pytest.mark.parametrize('n', [1, 300])
def test_one_fake_fleet_with_robot1_to_robot_n(n):
    values = params('fleet.launch', 'n:=%d' % n)
    assert values['/fake_fleet/robots'] == ['robot%d' % k for k in range(1, n + 1)]
    assert not any(name.startswith('/robot') for name in values)  # no courses


def test_one_course_per_robot_on_its_frames_and_own_tf():
    args = ('fleet.launch', 'n:=6', 'course:=true')
    courses = ['/robot%d/odom_out_and_back' % k for k in range(1, 7)]
    assert sorted(nodes(*args)) == sorted(['/fake_fleet'] + courses)
    values = params(*args)
    for k in range(1, 7):
        course = '/robot%d/odom_out_and_back/' % k
        assert values[course + 'odom_frame'] == 'robot%d/odom' % k
        assert values[course + 'base_frame'] == 'robot%d/base_footprint' % k
    command = node_command(courses[-1], *args)
    assert 'ROS_NAMESPACE="/robot6"' in command
    assert '/tf:=tf' in command.split() and '/tf_static:=tf_static' in command.split()


def test_a_large_fleet_gets_every_course():
    """The per-robot include nests log2(n) deep, not n (Python's recursion
    limit stops a linear chain of includes at a few hundred)."""
    started = nodes('fleet.launch', 'n:=400', 'course:=true')
    assert len(started) == 401 and '/robot400/odom_out_and_back' in started


def test_separate_runs_one_fake_turtlebot_per_robot_on_its_own_tf():
    args = ('fleet.launch', 'n:=3', 'separate:=true')
    values = params(*args)
    assert '/fake_fleet/robots' not in values
    for k in (1, 2, 3):
        assert values['/robot%d/fake_turtlebot/odom_frame' % k] == 'robot%d/odom' % k
        assert (values['/robot%d/fake_turtlebot/base_frame' % k]
                == 'robot%d/base_footprint' % k)
    command = node_command('/robot2/fake_turtlebot', *args).split()
    assert '/tf:=tf' in command and '/tf_static:=tf_static' in command


def test_the_last_course_to_succeed_ends_the_launch_unless_end_false():
    args = ('fleet.launch', 'n:=2', 'course:=true')
    wrapper = 'end_launch_on_success.py'
    assert wrapper in node_command('/robot2/odom_out_and_back', *args)
    assert wrapper not in node_command('/robot2/odom_out_and_back', *args, 'end:=false')
