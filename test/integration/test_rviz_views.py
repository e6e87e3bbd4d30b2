"""RViz for real, under Xvfb, with both of the package's views.

Each case starts a virtual screen, a simulated robot (realistic, so odometry
and ground truth drift apart) and RViz with one config, drives a short
out-and-back course, and takes a screenshot (kept in the workspace's
test_artifacts/). It passes when the screenshot shows the config's arrows:
the odometry (sim.rviz: red /odom; nav_ekf.rviz: green /odom_ekf) and the
ground truth (blue, both views), counted inside the 3D view, and RViz
logged no error.
"""
import os
import socket
import subprocess
import sys
import time

import pytest
import rosgraph

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, 'test', 'helpers'))
from rviz_screen import (BLUE, GREEN, MIN_PIXELS, RED, RVIZ_ENV,  # noqa: E402
                         Processes, colour_counts, rviz_errors)

CASES = {
    'sim.rviz': ('fake_turtlebot.launch', {'odometry (red)': RED,
                                           'ground truth (blue)': BLUE}),
    'nav_ekf.rviz': ('fake_turtlebot_ekf.launch', {'EKF odometry (green)': GREEN,
                                                   'ground truth (blue)': BLUE}),
}


def workspace():
    for prefix in os.environ.get('CMAKE_PREFIX_PATH', '').split(':'):
        if prefix.endswith('/devel'):
            return os.path.dirname(prefix)
    pytest.skip('not run from a sourced catkin devel space')


def free_port():
    with socket.socket() as s:
        s.bind(('localhost', 0))
        return s.getsockname()[1]


def wait_for_sim_time(uri, procs, limit=60.0):
    """Wait (wall time) until the master at ``uri`` has /use_sim_time true."""
    master = rosgraph.Master('/test_rviz_views', master_uri=uri)
    deadline = time.monotonic() + limit
    while time.monotonic() < deadline:
        try:
            if master.getParam('/use_sim_time') is True:
                return
        except Exception:  # no master yet, or no such parameter yet
            pass
        time.sleep(0.1)
    raise AssertionError('/use_sim_time not set %.0f s after roslaunch:\n%s'
                         % (limit, procs.log('robot')))


# One RViz at a time: RViz on software GL crashes now and then at its start
# ("free(): invalid next size", rviz_screen.RVIZ_ENV), the likelier the
# busier the machine; two at once did. The rostests that start RViz
# (book_lines.test) are in this group too (test_rostest_files.RVIZ).
@pytest.mark.xdist_group('rviz')
@pytest.mark.parametrize('config', sorted(CASES))
def test_rviz_draws_odometry_and_ground_truth(config, tmp_path):
    image_grab = pytest.importorskip('PIL.ImageGrab')
    if not os.path.exists('/usr/bin/Xvfb'):
        pytest.skip('Xvfb is not installed (make deps installs it)')
    launch, colours = CASES[config]
    artifacts = os.path.join(workspace(), 'test_artifacts')
    os.makedirs(artifacts, exist_ok=True)
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI='http://localhost:%d' % port,
               **RVIZ_ENV)
    procs = Processes(env, str(tmp_path))
    try:
        display = procs.start_xvfb()
        procs.start('robot', ['roslaunch', '-p', str(port), 'rbx1_nav', launch,
                              'sim_speed:=10', 'realistic:=true'])
        rviz = procs.start('rviz', ['rviz', '-d', os.path.join(ROOT, config)])
        # A course started before the launch sets /use_sim_time would run on
        # the wall clock while the robot runs at 10x (issue: the course
        # does not yet notice).
        wait_for_sim_time(env['ROS_MASTER_URI'], procs)
        course = subprocess.run(
            ['rosrun', 'rbx1_nav', 'odom_out_and_back.py', '_goal_distance:=0.5',
             '_pause:=0.2', '_tf_wait:=100', '_tf_timeout:=10'],
            env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
            universal_newlines=True, timeout=180)
        assert course.returncode == 0, course.stdout[-3000:]
        time.sleep(3.0)  # let RViz draw the last arrows (wall time: a screen)
        assert rviz.poll() is None, 'RViz exited:\n' + procs.log('rviz')
        shot = image_grab.grab(xdisplay=display)
    finally:
        procs.stop()
    path = os.path.join(artifacts, 'rviz_%s.png' % config[:-len('.rviz')])
    shot.save(path)
    counts = colour_counts(shot, colours)
    print('RESULT %s: %s; screenshot %s' % (config, counts, path))
    errors = rviz_errors(procs.log('rviz'))
    assert not errors, 'RViz logged errors:\n' + '\n'.join(errors)
    for name, count in counts.items():
        assert count >= MIN_PIXELS, '%s not drawn (%d pixels) in %s' % (
            name, count, path)
