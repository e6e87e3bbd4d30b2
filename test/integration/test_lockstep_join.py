"""A course joins a lockstep whose owner is slow to connect, and gives up
on one that has died.

Under lockstep a course waits ``~tf_wait`` for the node that grants steps
(sim_clock) to connect; on a loaded machine sim_clock can be registered,
alive and still not connected by then. The course keeps waiting while the
owner answers, saying so at each check (every NO_OWNER_WARNING wall s),
and once it has died gives up at its next check: no check after the kill
finds it alive, by the course's own log stamps. It never commands motion:
a watch on cmd_vel, connected to the course's publisher, hears nothing
but zero velocities. The owner here is a stand-in that never connects:
it publishes /clock and registers as the publisher of the grants, but
never takes the members' reports.
"""
import os
import re
import shutil
import signal
import subprocess
import sys
import time
import xmlrpc.client

import pytest
import rosgraph

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, '..', 'helpers'))
from master import HANG_GUARD, wait_for_master  # noqa: E402
from ports import free_port  # noqa: E402
from rosrun import rosrun  # noqa: E402
sys.path.insert(0, os.path.join(HERE, '..', 'faults'))
from test_two_hosts import Lines, come_up  # noqa: E402
from rbx1_nav.sim_time.member_grants_ros import NO_OWNER_WARNING as CHECK_PERIOD  # noqa: E402

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
COURSE = '/odom_out_and_back'


def start(cmd, env):
    return Lines(subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                  universal_newlines=True, start_new_session=True))


def kill(lines):
    try:
        os.killpg(lines.proc.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    lines.proc.wait()


def wall_stamp(line):
    """The wall time a rospy log line was written (its first stamp), or None."""
    found = re.match(r'\[\s*[A-Z]+\s*\]\s*\[([\d.]+)', line)
    return float(found.group(1)) if found else None


def stamped(lines, text):
    """The wall stamps of the log lines of ``lines`` that contain ``text``."""
    return [wall_stamp(line) for _, line in lines.lines if text in line]


def connected_to(master, node, topic):
    """The subscribers ``node``'s publisher of ``topic`` has a connection to
    (the node's getBusInfo, as rosnode info lists them)."""
    uri = master.lookupNode(node)
    code, message, info = xmlrpc.client.ServerProxy(uri).getBusInfo(master.caller_id)
    assert code == 1, message
    return {c[1] for c in info if c[2] == 'o' and c[4] == topic}


def twist_rows(watch):
    """The velocities (6 floats each) a ``rostopic echo -p`` of a Twist
    topic printed."""
    return [[float(v) for v in line.split(',')[1:]] for _, line in watch.lines
            if re.match(r'^\d+,', line)]


def kill_just_after_a_check(course, owner):
    """Kill ``owner`` within half a CHECK_PERIOD (wall s between a
    waiting course's checks of the owner) of a check that found it
    alive (a WAITING line, by its stamp), so the next check starts after
    the kill; returns the wall time of the kill."""
    seen = 0
    while True:
        come_up(lambda: len(stamped(course, WAITING)) > seen, [course, owner],
                'the course\'s next check of the owner')
        checks = stamped(course, WAITING)
        if time.time() - checks[-1] < CHECK_PERIOD / 2:
            kill(owner)  # stays registered with the master, answers no more
            return time.time()
        seen = len(checks)  # read late: wait for the next check


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
        watch = start(['rostopic', 'echo', '-p', '/cmd_vel'], env)
        procs.append(watch)
        course = start(rosrun('rbx1_nav', 'odom_out_and_back.py', '_tf_wait:=1.0'), env)
        procs.append(course)
        # Past its 1 s wait, alive: still waiting, saying for whom.
        _, line = course.wait_for(WAITING)
        assert course.proc.poll() is None, course.text()
        assert '/sim_clock' in line, course.text()
        # The watch hears whatever the course would command from here on.
        come_up(lambda: connected_to(master, COURSE, '/cmd_vel'), [course, watch],
                'the cmd_vel watch connected to the course')
        killed = kill_just_after_a_check(course, owner)
        # Until it exits, or a check after the kill finds the dead owner alive.
        come_up(lambda: course.proc.poll() is not None
                or any(t > killed for t in stamped(course, WAITING)), [],
                'the course\'s exit', HANG_GUARD)
        assert [t for t in stamped(course, WAITING) if t > killed] == [], (
            'a check after the kill found the owner alive:\n' + course.text())
        status = course.proc.wait()
        text = course.text()
        assert status == 1, text
        assert GONE in text and stamped(course, GONE)[0] > killed, text
        assert 'Course complete' not in text, text
        # Its last command is the stop on the way out, written before it
        # exits (a lockstep member's publisher is synchronous): once the
        # watch has it, it has every command the course sent.
        come_up(lambda: twist_rows(watch), [watch], 'the course\'s stop on cmd_vel')
        velocities = twist_rows(watch)
        print('RESULT the course gave up %.2f s (wall) after its owner died, %.2f s (wall) '
              'after its last check found it alive (one every %.0f s wall); cmd_vel: %d '
              'velocities heard, %d asking for motion'
              % (stamped(course, GONE)[0] - killed,
                 stamped(course, GONE)[0] - stamped(course, WAITING)[-1], CHECK_PERIOD,
                 len(velocities), sum(map(any, velocities))))
        assert not any(map(any, velocities)), watch.text()
    finally:
        for lines in reversed(procs):
            kill(lines)
