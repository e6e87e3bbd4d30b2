"""A course joins a lockstep whose owner is slow to connect, and gives up
on one that has died.

Under lockstep a course waits ``~tf_wait`` for the node that grants steps
(sim_clock) to connect; on a loaded machine sim_clock can be registered,
alive and still not connected by then. The course keeps waiting while the
owner answers, saying so, and gives up at once, with the robot unmoved,
once it has died. The owner here is a stand-in that never connects: it
publishes /clock and registers as the publisher of the grants, but never
takes the members' reports.
"""
import os
import shutil
import signal
import subprocess
import sys
import time

import pytest
import rosgraph

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, '..', 'helpers'))
from master import HANG_GUARD, wait_for_master  # noqa: E402
from ports import free_port  # noqa: E402
from rosrun import rosrun  # noqa: E402
sys.path.insert(0, os.path.join(HERE, '..', 'faults'))
from test_two_hosts import Lines  # noqa: E402

pytestmark = pytest.mark.skipif(
    not shutil.which('rosrun') or 'ROS_PACKAGE_PATH' not in os.environ,
    reason='needs a sourced ROS workspace (make test sources one)')

PORTS = range(11500, 11506)
OWNER = '''
import rospy
from rosgraph_msgs.msg import Clock
from rbx1_nav.msg import LockstepGrant
rospy.init_node('sim_clock')
clock = rospy.Publisher('/clock', Clock, queue_size=1)
grants = rospy.Publisher('/lockstep_grant', LockstepGrant, queue_size=1)
now = rospy.Time(1)
while True:
    clock.publish(Clock(clock=now))
    rospy.rostime.wallsleep(0.1)
'''
WAITING = 'is up but not yet connected'
GONE = 'nothing grants lockstep steps on /lockstep_grant'


def start(cmd, env):
    return Lines(subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                  universal_newlines=True, start_new_session=True))


def kill(lines):
    try:
        os.killpg(lines.proc.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    lines.proc.wait()


def test_a_course_waits_for_a_live_owner_and_not_for_a_dead_one(tmp_path):
    port = free_port(PORTS)
    env = dict(os.environ, ROS_MASTER_URI='http://localhost:%d' % port,
               ROS_LOG_DIR=str(tmp_path), PYTHONUNBUFFERED='1')
    env.pop('ROS_NAMESPACE', None)
    procs = []
    try:
        core = start(['rosmaster', '--core', '-p', str(port)], env)
        procs.append(core)
        wait_for_master(env['ROS_MASTER_URI'], core.proc, core.text)
        master = rosgraph.Master('/test_lockstep_join', master_uri=env['ROS_MASTER_URI'])
        for name in ('/use_sim_time', '/lockstep'):
            master.setParam(name, True)
        owner = start([sys.executable, '-c', OWNER], env)
        procs.append(owner)
        course = start(rosrun('rbx1_nav', 'odom_out_and_back.py', '_tf_wait:=1.0'), env)
        procs.append(course)
        # Past its 1 s wait, alive: still waiting, saying for whom.
        _, line = course.wait_for(WAITING)
        assert course.proc.poll() is None, course.text()
        assert '/sim_clock' in line, course.text()
        kill(owner)  # stays registered with the master, answers no more
        started = time.monotonic()
        status = course.proc.wait(HANG_GUARD)
        waited = time.monotonic() - started
        text = course.text()
        assert status == 1, text
        assert GONE in text, text
        assert 'Course complete' not in text, text
        # The next check of the owner ends it: within NO_OWNER_WARNING (5 s)
        # of wall time plus start-up of nothing (hang guard only).
        print('the course gave up %.1f s after its owner died' % waited)
    finally:
        for lines in reversed(procs):
            kill(lines)
