"""SIGINT while a node starts: it ends quietly, with no traceback.

roslaunch sends SIGINT to every node of a launch that ends, some of them
still being imported: a second ``roslaunch rbx1_bringup
fake_turtlebot.launch`` ends at once (a robot is already up), and its
pose_ekf printed a KeyboardInterrupt traceback from the middle of
``import sensor_msgs.msg``. A node file's first line gives SIGINT its
default action (the process ends, silently) until start_node takes the
signals over, and a shutdown during rospy.init_node ends the node quietly.

The signal comes at chosen points, the same on every run, not after a
wall-clock delay: the node runs under a small wrapper (``HOOK``) that sends
SIGINT to its own process when the node is about to import a given
module, or right after a given call returns (then it waits for the
shutdown the signal starts, as a slow start-up would meet it). The wrapper
says on stderr that it sent it, so a node that ended by itself does not
pass. The interpreter's own start (its ``site`` imports, before the node's
first line runs) stays open to a traceback: no line of the package runs
then.

Each test starts its own master (rosmaster, no rosout) on a free port.
"""
import os
import shutil
import signal
import subprocess
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'helpers'))
from master import wait_for_master  # noqa: E402
from ports import free_port  # noqa: E402
from rosrun import node_path  # noqa: E402

pytestmark = pytest.mark.skipif(
    not shutil.which('rosmaster') or 'ROS_PACKAGE_PATH' not in os.environ,
    reason='needs a sourced ROS workspace (make test sources one)')

PORTS = range(11440, 11450)
SENT = 'HOOK: SIGINT sent'

#: Runs the node file argv[1] as rosrun does (the devel space's relay
#: executes it as __main__), sending SIGINT at argv[2]: ``import:MODULE``
#: (as the node is about to import it) or ``call:MODULE:NAME`` (after the
#: call returns; the wrapper then waits for the shutdown it starts).
HOOK = r'''
import importlib, importlib.abc, os, runpy, signal, sys, time
node, when = sys.argv[1], sys.argv[2]


def interrupt():
    sys.stderr.write('%s at %s\n' % (SENT, when))
    sys.stderr.flush()
    os.kill(os.getpid(), signal.SIGINT)


if when.startswith('import:'):
    module = when[len('import:'):]

    class Finder(importlib.abc.MetaPathFinder):
        def find_spec(self, name, path=None, target=None):
            if name == module:
                sys.meta_path.remove(self)
                interrupt()
            return None
    sys.meta_path.insert(0, Finder())
else:
    import rospy.core
    module, path = when[len('call:'):].split(':')
    owner = importlib.import_module(module)
    *within, attr = path.split('.')
    for part in within:  # a class's method
        owner = getattr(owner, part)
    original = getattr(owner, attr)

    def wrapped(*args, **kwargs):
        result = original(*args, **kwargs)
        if not rospy.core.is_shutdown_requested():
            interrupt()
            while not rospy.core.is_shutdown_requested():
                time.sleep(0.01)
        return result
    setattr(owner, attr, wrapped)
sys.argv = [node] + sys.argv[3:]
runpy.run_path(node, run_name='__main__')
'''.replace('SENT', repr(SENT))


@pytest.fixture(scope='module')
def master(tmp_path_factory):
    """The environment of a master of this file's own."""
    port = free_port(PORTS)
    log = tmp_path_factory.mktemp('start_signals')
    env = dict(os.environ, ROS_MASTER_URI='http://localhost:%d' % port,
               ROS_LOG_DIR=str(log), PYTHONUNBUFFERED='1')
    out = open(str(log / 'rosmaster.log'), 'w')
    proc = subprocess.Popen(['rosmaster', '--core', '-p', str(port)], env=env,
                            stdout=out, stderr=subprocess.STDOUT, start_new_session=True)
    try:
        wait_for_master(env['ROS_MASTER_URI'], proc)
        yield env
    finally:
        proc.send_signal(signal.SIGINT)
        try:
            proc.wait(15)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
        out.close()


def interrupted(env, script, when, *args):
    """Run ``script`` with SIGINT at ``when``; (exit status, stderr)."""
    done = subprocess.run([sys.executable, '-c', HOOK, node_path(script), when] + list(args),
                          env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          universal_newlines=True, timeout=120)
    assert SENT in done.stderr, 'the signal was never sent (%s never came):\n%s%s' % (
        when, done.stdout, done.stderr)
    return done.returncode, done.stderr


# Through the imports of pose_ekf.py (as roslaunch met it, in sensor_msgs),
# rospy.init_node, and the start-up after it.
POSE_EKF_POINTS = ['import:rbx1_nav', 'import:rospy', 'import:numpy', 'import:sensor_msgs.msg',
                   'import:tf2_ros', 'call:rospy.impl.init:start_node', 'call:rospy:get_param',
                   'call:rospy.topics:Subscriber.__init__']


@pytest.mark.parametrize('when', POSE_EKF_POINTS)
def test_pose_ekf_interrupted_while_it_starts_ends_without_a_traceback(master, when):
    status, err = interrupted(master, 'pose_ekf.py', when, '__name:=robot_pose_ekf_sigint')
    print('RESULT pose_ekf SIGINT at %s: exit %s, stderr %r' % (when, status, err[-200:]))
    assert 'Traceback' not in err, err
    assert 'KeyboardInterrupt' not in err, err
    # Killed by the signal (during the imports), or status 1 (a shutdown
    # during init_node) or 0 (started, then stopped by it): never a crash.
    assert status in (-signal.SIGINT, 0, 1), (status, err)
    assert len([line for line in err.splitlines() if SENT not in line]) <= 1, err


#: Every node that starts through rbx1_nav.common.node_ros or ends a launch.
NODES = ['calibrate_angular.py', 'calibrate_linear.py', 'fake_fleet.py', 'fake_turtlebot.py',
         'lockstep_play.py', 'nav_square.py', 'odom_ekf.py', 'odom_out_and_back.py',
         'sim_clock.py', 'teleop_keyboard.py', 'timed_out_and_back.py', 'umbmark.py',
         'unless_running.py', 'end_launch_on_success.py', 'launch_status.py']


@pytest.mark.parametrize('script', NODES)
def test_every_node_interrupted_during_its_imports_ends_quietly(master, script):
    status, err = interrupted(master, script, 'import:rbx1_nav.common')
    assert 'Traceback' not in err, err
    assert status == -signal.SIGINT, (status, err)
