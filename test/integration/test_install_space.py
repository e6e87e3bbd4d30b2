"""The package as installed: ``make install`` of the workspace that runs the
tests, then, in a clean environment with only the install space set up and
the source tree on no path: the book's cfg modules import as the book's
scripts do (``from rbx1_nav.cfg import CalibrateLinearConfig``, checked from
the devel space too), the demo course completes as ``make demo`` runs it
(recorded to a bag, then plotted) and its launch ends cleanly, and a
rostest passes.

The demo and the rostest here are the only launches of make test that read
the system's own roscore.xml, whose parameters run rosversion: every other
launch reads the suite's answered copy (test/helpers/ros_etc.py), which
must give the same parameters.
"""
import math
import os
import re
import socket
import subprocess
import sys
import xml.etree.ElementTree as ElementTree

import pytest
import roslaunch.config
import rospkg

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'helpers'))
from course_model import reference_end_pose  # noqa: E402

IMPORT = ('import rbx1_nav, rbx1_nav.motion.runner.runner_ros; '
          'from rbx1_nav.cfg import CalibrateLinearConfig as L, '
          'CalibrateAngularConfig as A; '
          'print(rbx1_nav.__file__); print(sorted(L.defaults)); '
          'print(sorted(A.defaults))')
LINEAR_FIELDS = ['measured_distance', 'odom_linear_scale_correction', 'speed',
                 'start_test', 'test_distance', 'tolerance']
ANGULAR_FIELDS = ['measured_angle', 'odom_angular_scale_correction', 'speed',
                  'start_test', 'test_angle', 'tolerance']
SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(
    os.path.abspath(__file__))))
# One install space per run: its tests go to one worker (make test's
# --dist loadgroup).
pytestmark = pytest.mark.xdist_group('install_space')
sys.path.insert(0, os.path.join(SOURCE, 'test', 'helpers'))
import ros_etc  # noqa: E402

#: Put before a command of run_in that launches: the ROS_ETC_DIR the
#: install space's setup leaves (unset: rospkg's default, /etc/ros).
SHOW_ETC = 'echo "ROS_ETC_DIR=${ROS_ETC_DIR-}"; '


def workspace():
    """The catkin workspace whose devel space the tests run in."""
    for prefix in os.environ.get('CMAKE_PREFIX_PATH', '').split(':'):
        if prefix.endswith('/devel') and os.path.isdir(
                os.path.join(prefix, '..', 'build')):
            return os.path.dirname(prefix)
    pytest.skip('not run from a sourced catkin devel space')


def run_in(setup, command, timeout=120):
    """Run ``command`` (bash) with only ``setup`` sourced, from /tmp."""
    return subprocess.run(
        ['env', '-i', 'HOME=' + os.environ.get('HOME', '/root'),
         'PATH=/usr/bin:/bin', 'bash', '-c',
         'source %s && cd /tmp && %s' % (setup, command)],
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
        universal_newlines=True, timeout=timeout)


def assert_system_etc(output):
    """The launch of a SHOW_ETC command (its ``output``) read a roscore.xml
    whose parameters run commands: the system's own, not the suite's
    answered copy (in this process's ROS_ETC_DIR)."""
    shown = re.search(r'^ROS_ETC_DIR=(.*)$', output, re.M)
    assert shown, output[-3000:]
    etc = rospkg.get_etc_ros_dir({'ROS_ETC_DIR': shown.group(1)} if shown.group(1) else {})
    commands = ros_etc.command_params(ElementTree.parse(os.path.join(etc, 'roscore.xml')))
    assert commands, '%s (ROS_ETC_DIR %s) runs no command: not the system\'s own' % (
        os.path.join(etc, 'roscore.xml'), os.environ.get('ROS_ETC_DIR'))


def paths_under(text, root):
    """The absolute paths in ``text`` (env's lines, rospack's output) that
    are ``root`` or inside it, compared by path components: a checkout in
    ``ci4`` is no part of a HOME in ``ci4home`` beside it."""
    root = os.path.normpath(root)
    return [token for token in re.split(r'[\s:;=]+', text) if token.startswith('/')
            and os.path.commonpath([os.path.normpath(token), root]) == root]


def check_imports(setup, space):
    proc = run_in(setup, 'python3 -c "%s"' % IMPORT)
    assert proc.returncode == 0, proc.stdout
    module, linear, angular = proc.stdout.splitlines()[-3:]
    assert module.startswith(space), module
    assert linear == str(LINEAR_FIELDS)
    assert angular == str(ANGULAR_FIELDS)


@pytest.fixture(scope='module')
def install_setup():
    """``make install`` the workspace; the install space's local_setup.bash.

    Not setup.bash: that one chains the workspaces the build saw (its devel
    space, and through it the source tree); local_setup.bash sets up the
    install space alone, over the system's ROS.
    """
    ws = workspace()
    build = subprocess.run(['flock', os.path.join(ws, '.build.lock'),
                            'make', '-C', os.path.join(ws, 'build'), 'install'],
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           universal_newlines=True, timeout=300)
    assert build.returncode == 0, build.stdout[-3000:]
    return os.path.join(ws, 'install', 'local_setup.bash')


def test_cfg_modules_import_from_the_devel_space():
    ws = workspace()
    # In devel, rbx1_nav is catkin's relay package; it finds src/ and cfg/.
    check_imports(os.path.join(ws, 'devel', 'setup.bash'),
                  os.path.join(ws, 'devel'))


def test_cfg_modules_import_from_the_install_space(install_setup):
    check_imports(install_setup, os.path.dirname(install_setup))


def test_the_source_tree_is_on_no_path(install_setup):
    proc = run_in(install_setup, 'rospack find rbx1_nav; env | grep -v ^OLDPWD=')
    assert proc.returncode == 0, proc.stdout
    assert proc.stdout.splitlines()[0].startswith(os.path.dirname(install_setup))
    for source in (SOURCE, os.path.join(workspace(), 'src')):
        assert paths_under(proc.stdout, source) == [], proc.stdout


def test_the_books_files_are_found_from_the_install_space(install_setup):
    """What the book's lines name: rbx1_bringup's launch files and the RViz
    views at rbx1_nav's root (rviz -d `rospack find rbx1_nav`/sim.rviz)."""
    proc = run_in(install_setup, 'ls `rospack find rbx1_nav`/sim.rviz '
                  '`rospack find rbx1_nav`/nav_ekf.rviz && '
                  'roslaunch --files rbx1_bringup fake_turtlebot.launch && '
                  'roslaunch --files rbx1_bringup odom_ekf.launch')
    assert proc.returncode == 0, proc.stdout
    space = os.path.dirname(install_setup)
    for line in proc.stdout.split():
        assert line.startswith(space), proc.stdout


#: The demo's true end against the pure model's (test/helpers/course_model.py):
#: under lockstep the graph takes the model's steps, so only floating point
#: parts them (book_lines.test's bounds: 0.1 mm, 0.01 deg).
MATCH = (0.0001, 0.01)  # m, deg
#: plot_course's title rounds to 0.1 mm and 0.01 deg.
ROUNDING = (0.0501, 0.00501)  # mm, deg


def bag_tracks(path):
    """{'ground truth': poses, 'odom': poses} of a course's bag, each
    (x, y, yaw) in the order recorded."""
    import rosbag
    from rbx1_nav.transform_utils import quat_to_angle
    names = {'ground_truth': 'ground truth', 'odom': 'odom'}
    tracks = {name: [] for name in names.values()}
    with rosbag.Bag(path) as bag:  # names as recorded: relative ones without a '/'
        for topic, msg, _ in bag.read_messages(topics=list(names) + ['/' + t for t in names]):
            p = msg.pose.pose
            tracks[names[topic.strip('/')]].append(
                (p.position.x, p.position.y, quat_to_angle(p.orientation)))
    return tracks


def end_vs_start(poses):
    """(mm, deg) from a track's first pose to its last."""
    (x0, y0, a0), (x1, y1, a1) = poses[0], poses[-1]
    return (1e3 * math.hypot(x1 - x0, y1 - y0),
            math.degrees(math.remainder(a1 - a0, 2 * math.pi)))


def check_plot(setup, bag, tracks):
    """plot_course.py on ``bag`` from the install space, as make demo runs
    it: the numbers in its figure's title (the PNG holds it as its Title)
    are the bag's, each track's end against its start, and odometry's end
    against the ground truth's."""
    from PIL import Image
    png = os.path.splitext(bag)[0] + '.png'
    proc = run_in(setup, 'rosrun rbx1_nav plot_course.py %s -o %s' % (bag, png))
    assert proc.returncode == 0, proc.stdout[-3000:]
    with Image.open(png) as image:
        title = image.text['Title']
    drawn = {name: (float(mm), float(deg)) for name, mm, deg in re.findall(
        r'(odom|ground truth): ([\d.]+) mm, ([-+\d.]+) deg', title)}
    assert set(drawn) == set(tracks), title
    for name, (mm, deg) in drawn.items():
        truth = end_vs_start(tracks[name])
        assert abs(mm - truth[0]) < ROUNDING[0] and abs(deg - truth[1]) < ROUNDING[1], (
            name, truth, title)
    apart = re.search(r'at the end: odom: ([\d.]+) mm from ground truth', title)
    (x, y, _), (tx, ty, _) = tracks['odom'][-1], tracks['ground truth'][-1]
    assert apart and abs(float(apart.group(1)) - 1e3 * math.hypot(x - tx, y - ty)) < ROUNDING[0], (
        title)
    return title


def test_demo_course_completes_from_the_install_space(install_setup, tmp_path):
    with socket.socket() as s:  # a free port for this launch's own master
        s.bind(('localhost', 0))
        port = s.getsockname()[1]
    bag = str(tmp_path / 'course.bag')
    # As make demo runs it: through launch_status.py (roslaunch exits 0
    # whatever the course did), recorded to a bag.
    proc = run_in(install_setup, SHOW_ETC + 'export ROS_MASTER_URI=http://localhost:%d; '
                  'rosrun rbx1_nav launch_status.py rbx1_nav odom_out_and_back_sim.launch '
                  'sim_speed:=10 record:=true bag:=%s' % (port, bag))
    assert proc.returncode == 0, proc.stdout[-3000:]
    # It read the system's roscore.xml, and its parameters are those the
    # suite's answered copy gives every other launch (as roslaunch's
    # summary prints them: trailing whitespace stripped).
    assert_system_etc(proc.stdout)
    answered = roslaunch.config.load_config_default([], None, verbose=False).params
    assert answered
    for name, param in answered.items():
        shown = re.search(r'^ \* %s: (.*)$' % re.escape(name), proc.stdout, re.M)
        assert shown and shown.group(1) == str(param.value).rstrip(), (
            '%s: the system\'s roscore.xml gave %r, the suite\'s answered copy %r' % (
                name, shown and shown.group(1), param.value))
    assert proc.stdout.rstrip().endswith('launch_status: odom_out_and_back exited 0'), (
        proc.stdout[-3000:])
    assert 'error from the ideal end pose' in proc.stdout, proc.stdout[-3000:]
    # The launch ends cleanly after the course (end_launch_on_success.py),
    # without roslaunch's red block for a required node's end.
    assert 'finished cleanly: ending the launch' in proc.stdout, proc.stdout[-3000:]
    assert 'REQUIRED process' not in proc.stdout, proc.stdout[-3000:]
    # The ideal robot from the origin, under lockstep: where the pure
    # model's course ends, by the bag's ground truth (the robot stands
    # still there from the course's end to the launch's).
    tracks = bag_tracks(bag)
    (x, y, yaw), model = tracks['ground truth'][-1], reference_end_pose({})
    off = math.hypot(x - model.x, y - model.y)
    turn = math.degrees(math.remainder(yaw - model.yaw, 2 * math.pi))
    title = check_plot(install_setup, bag, tracks)
    print('RESULT demo course end (%.6f, %.6f, %.4f deg), model (%.6f, %.6f, %.4f deg): '
          'off by %.4f mm, %.5f deg; its plot says: %s' % (
              x, y, math.degrees(yaw), model.x, model.y, math.degrees(model.yaw),
              1e3 * off, turn, ' / '.join(title.splitlines())))
    assert off < MATCH[0] and abs(turn) < MATCH[1]


def test_a_rostest_passes_from_the_install_space(install_setup):
    proc = run_in(install_setup, SHOW_ETC + 'rostest rbx1_nav out_and_back_no_tf.test')
    assert proc.returncode == 0, proc.stdout[-3000:]
    assert_system_etc(proc.stdout)
