"""The RViz views fit a laptop screen and close without a prompt; every
launch file argument is documented and none is required (checked through
``roslaunch --ros-args``, which calls an argument without a default, or with
an empty one, required); every node starts with clean private parameters,
a required node ends its launch without roslaunch's red block, and a
launch that starts a robot sets /use_sim_time."""
import glob
import os
import shutil
import sys
from xml.etree import ElementTree

import pytest
import yaml

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'helpers'))
import launch_reading  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
RVIZ = sorted(glob.glob(os.path.join(ROOT, 'rviz', '*.rviz')))
# rbx1_nav's, and rbx1_bringup's (the package the book's lines start
# from, in the hidden .rbx1_bringup/: see test_the_books_names_find_one_file).
BRINGUP = os.path.join(ROOT, '.rbx1_bringup')
LAUNCH = sorted(glob.glob(os.path.join(ROOT, 'launch', '*.launch'))
                + glob.glob(os.path.join(BRINGUP, 'launch', '*.launch')))
SCREEN = (1280, 800)  # a common laptop screen


@pytest.mark.parametrize('path', RVIZ, ids=[os.path.basename(p) for p in RVIZ])
def test_rviz_window_fits_the_screen_and_closes_without_a_prompt(path):
    with open(path) as f:
        config = yaml.safe_load(f)
    window = config['Window Geometry']
    assert window['X'] + window['Width'] <= SCREEN[0]
    assert window['Y'] + window['Height'] <= SCREEN[1]
    assert config['Preferences']['PromptSaveOnExit'] is False


@pytest.mark.parametrize('path', LAUNCH, ids=[os.path.basename(p) for p in LAUNCH])
def test_launch_arguments_are_documented_and_optional(path):
    """What `roslaunch --ros-args` and `roslaunch --nodes` check, in this
    process (a roslaunch each costs a second of CPU)."""
    if 'ROS_PACKAGE_PATH' not in os.environ:
        pytest.skip('needs a sourced ROS workspace (make test sources one)')
    import roslaunch.arg_dump
    import roslaunch.config
    args = roslaunch.arg_dump.get_args([path])
    assert [name for name, (_, default) in args.items() if default is None] == []
    assert [name for name, (doc, _) in args.items() if doc is None] == []
    # Every substitution evaluated ($(eval ...) in attributes too).
    config = roslaunch.config.load_config_default([path], None, verbose=False)
    assert config.nodes or config.tests


LAUNCH_XML = LAUNCH + sorted(glob.glob(os.path.join(ROOT, 'launch', 'include', '*.xml')))


def test_the_books_names_find_one_file():
    """`roslaunch rbx1_nav fake_turtlebot.launch` and the book's
    `roslaunch rbx1_bringup fake_turtlebot.launch` each find one file
    (roslaunch searches every folder of a package but hidden ones, and
    refuses a name it finds twice), and `rospack find rbx1_nav`/sim.rviz
    is the view in rviz/ (one copy of each view: the root has links)."""
    if 'ROS_PACKAGE_PATH' not in os.environ:
        pytest.skip('needs a sourced ROS workspace (make test sources one)')
    import rospkg
    from roslib.packages import find_resource
    rospack = rospkg.RosPack()
    for package, folder in (('rbx1_nav', os.path.join(ROOT, 'launch')),
                            ('rbx1_bringup', os.path.join(BRINGUP, 'launch'))):
        for name in os.listdir(folder):
            if name.endswith('.launch'):
                found = find_resource(package, name, rospack=rospack)
                assert len(found) == 1, (package, name, found)
    for view in ('sim.rviz', 'nav_ekf.rviz'):
        path = os.path.join(rospack.get_path('rbx1_nav'), view)
        assert os.path.realpath(path) == os.path.join(ROOT, 'rviz', view)
WRAPPER = '$(find rbx1_nav)/end_launch_on_success.py'


def nodes_of(path):
    return ElementTree.parse(path).getroot().iter('node')


@pytest.mark.parametrize('path', LAUNCH_XML, ids=[os.path.basename(p) for p in LAUNCH_XML])
def test_every_node_starts_with_clean_private_parameters(path):
    for node in nodes_of(path):
        assert node.get('clear_params') == 'true', node.attrib


@pytest.mark.parametrize('path', LAUNCH_XML, ids=[os.path.basename(p) for p in LAUNCH_XML])
def test_a_node_that_ends_its_launch_ends_it_cleanly_on_success(path):
    """Without end_launch_on_success.py, roslaunch ends a launch whose
    required node finished with a red "REQUIRED process ... has died!"."""
    wrapper = [arg for arg in ElementTree.parse(path).getroot().iter('arg')
               if arg.get('name') == 'wrapper' and arg.get('value') == WRAPPER]
    for node in nodes_of(path):
        if node.get('required') == 'true':
            prefix = node.get('launch-prefix', '')
            assert WRAPPER in prefix or (wrapper and "arg('wrapper')" in prefix), node.attrib


def dump_params(launch, *args):
    """The parameters ``roslaunch --dump-params rbx1_nav LAUNCH ARGS`` lists."""
    if not shutil.which('roslaunch') or 'ROS_PACKAGE_PATH' not in os.environ:
        pytest.skip('needs a sourced ROS workspace (make test sources one)')
    return launch_reading.params(launch, *args)


@pytest.mark.parametrize('args, sim_time', [
    (['fake_turtlebot.launch'], False),
    (['fake_turtlebot.launch', 'sim_speed:=5'], True),
    (['nav_square.launch', 'sim:=true'], False),
    (['umbmark.launch', 'sim:=true', 'sim_speed:=max'], True),
    (['odom_out_and_back_sim.launch'], False),
    (['fleet.launch', 'n:=2'], False),
    (['fleet.launch', 'n:=2', 'sim_speed:=max'], True),
])
def test_a_launch_that_starts_a_robot_sets_use_sim_time(args, sim_time):
    """A launch with sim_speed killed before its sim_clock removed
    /use_sim_time leaves it true on the master: a later real-time launch
    must set it back."""
    assert dump_params(*args)['/use_sim_time'] is sim_time


@pytest.mark.parametrize('launch', ['fake_turtlebot.launch',
                                    os.path.join(BRINGUP, 'launch', 'fake_turtlebot.launch')],
                         ids=['rbx1_nav', 'rbx1_bringup'])
def test_the_fake_robot_takes_its_commands_where_cmd_vel_says(launch):
    """`roslaunch ... fake_turtlebot.launch cmd_vel:=mobile_base/commands/velocity`
    stands in a TurtleBot 2: the fake robot's command line remaps its
    cmd_vel; without the argument it has no remap of cmd_vel, which would
    replace one made around the include (test/rostest/turtlebot2_remap.test)."""
    dump_params('fake_turtlebot.launch')  # skips without a sourced workspace
    given = launch_reading.node_command('/fake_turtlebot', launch, 'realistic:=true',
                                        'cmd_vel:=mobile_base/commands/velocity').split()
    assert 'cmd_vel:=mobile_base/commands/velocity' in given, given
    plain = launch_reading.node_command('/fake_turtlebot', launch).split()
    assert not [word for word in plain if word.startswith('cmd_vel:=')], plain
