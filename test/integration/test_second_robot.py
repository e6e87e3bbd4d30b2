"""The fake robot started a second time, as docs/courses.md's lines invite
(fake_turtlebot.launch, then a course's launch with sim:=true): the second
launch says a robot is already up and ends; the first robot, its
robot_state_publisher among its nodes, goes on, unmoved, and still drives.

And a node the master mistakes for another one: rosmaster asks a node
to shut down when a new node takes its name, at the address the old one
registered, which another node may have since (ros/ros_comm#2241): the
package's nodes refuse a request that names another node.

Each test starts its own roscore on a free port and kills every process it
started (rbx1_nav.common.already_up)."""
import os
import shutil
import subprocess
import sys
import time
import xmlrpc.client

import pytest
import rosgraph

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'helpers'))
from master import HANG_GUARD, end_processes, node_pid, wait_for_master  # noqa: E402
from ports import free_port  # noqa: E402
from rosrun import rosrun  # noqa: E402

pytestmark = pytest.mark.skipif(
    not shutil.which('roslaunch') or 'ROS_PACKAGE_PATH' not in os.environ,
    reason='needs a sourced ROS workspace (make test sources one)')

PORTS = range(11472, 11490)
LINE = 'a fake robot is already running as /fake_turtlebot'


class Graph(object):
    """A roscore of its own on a free port, the processes started on it, and
    the master's and the nodes' answers asked from this process (a rosnode
    or rosparam process costs a third of a CPU second)."""

    def __init__(self, tmp_path):
        port = free_port(PORTS)
        self.env = dict(os.environ, ROS_MASTER_URI='http://localhost:%d' % port,
                        ROS_LOG_DIR=str(tmp_path), PYTHONUNBUFFERED='1')
        self.procs = []
        self.tmp = tmp_path
        roscore = self.start(['roscore', '-p', str(port)], 'roscore')
        wait_for_master(self.env['ROS_MASTER_URI'], roscore, lambda: self.output('roscore'))
        self.master = rosgraph.Master('/test_graph', master_uri=self.env['ROS_MASTER_URI'])

    def start(self, cmd, log):
        out = open(str(self.tmp / (log + '.log')), 'w')
        proc = subprocess.Popen(cmd, env=self.env, stdout=out,
                                stderr=subprocess.STDOUT, start_new_session=True)
        self.procs.append(proc)
        return proc

    def output(self, log):
        with open(str(self.tmp / (log + '.log'))) as f:
            return f.read()

    def run(self, cmd, timeout=20):
        return subprocess.run(cmd, env=self.env, stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT,
                              universal_newlines=True, timeout=timeout)

    def wait_for(self, ready, what, proc, log):
        """Until ``ready()``, while ``proc`` (logging to ``log``) lives;
        HANG_GUARD wall seconds alive is a hang."""
        started = time.monotonic()
        while not ready():
            assert proc.poll() is None, 'no %s: it ended (exit %s):\n%s' % (
                what, proc.returncode, self.output(log))
            assert time.monotonic() - started < HANG_GUARD, 'no %s after %.0f s alive' % (
                what, HANG_GUARD)
            time.sleep(0.5)

    def nodes(self):
        """The nodes with a topic or service, as ``rosnode list`` has them."""
        state = self.master.getSystemState()
        return {node for entries in state for _, nodes in entries for node in nodes}

    def node_pid(self, name):
        return node_pid(self.master, name)

    def follow_x(self, topic='/ground_truth'):
        """A recorder of the x of ``topic``'s pose; :meth:`last_x` reads it."""
        proc = self.start(['rostopic', 'echo', topic + '/pose/pose/position/x'], 'x')
        self.wait_for(lambda: self.last_x() is not None, topic, proc, 'x')
        return proc

    def last_x(self):
        """The x the recorder of :meth:`follow_x` printed last, or None."""
        values = [line for line in self.output('x').split('\n---\n')[:-1] if line.strip()]
        return float(values[-1]) if values else None

    def close(self):
        end_processes(self.procs, 15)


@pytest.fixture
def graph(tmp_path):
    g = Graph(tmp_path)
    yield g
    g.close()


@pytest.mark.parametrize('second', [
    ['roslaunch', 'rbx1_nav', 'nav_square.launch', 'sim:=true'],
    ['roslaunch', 'rbx1_nav', 'fake_turtlebot.launch', 'sim_speed:=5'],
], ids=['nav_square_sim', 'fake_turtlebot_sim_speed'])
def test_a_second_robot_is_refused_and_the_first_goes_on(graph, second):
    first = graph.start(['roslaunch', 'rbx1_nav', 'fake_turtlebot.launch'], 'first')
    graph.wait_for(lambda: {'/fake_turtlebot', '/robot_state_publisher'} <= graph.nodes(),
                   'first robot', first, 'first')
    pids = {name: graph.node_pid(name)
            for name in ('/fake_turtlebot', '/robot_state_publisher')}

    again = graph.start(second, 'second')
    try:
        again.wait(HANG_GUARD)
    except subprocess.TimeoutExpired:
        pytest.fail('the second launch did not end:\n' + graph.output('second'))
    out = graph.output('second')
    print(out)
    assert LINE in out, out
    assert 'nav_square.launch' in out and 'rosnode kill /fake_turtlebot' in out

    # The first launch and its nodes go on: the same processes, answering.
    assert first.poll() is None, graph.output('first')
    for name, pid in pids.items():
        assert graph.node_pid(name) == pid, (name, graph.output('first'))
    # Real time, as the first launch set it: false, or absent (which every
    # node reads as false) once the refused launch's own sim_clock, if it
    # got as far as starting, removed it as that launch ended.
    assert (not graph.master.hasParam('/use_sim_time')
            or graph.master.getParam('/use_sim_time') is False)
    # Unmoved by the second launch's course, and it still drives.
    graph.follow_x()
    assert abs(graph.last_x()) < 1e-9
    drive = graph.start(['rostopic', 'pub', '-r', '20', '/cmd_vel', 'geometry_msgs/Twist',
                         '{linear: {x: 0.2}}'], 'drive')
    graph.wait_for(lambda: graph.last_x() > 0.05, 'motion of the first robot', drive, 'drive')


def test_a_shutdown_meant_for_another_node_is_refused(graph):
    robot = graph.start(rosrun('rbx1_nav', 'fake_turtlebot.py'), 'robot')
    graph.wait_for(lambda: '/fake_turtlebot' in graph.nodes(), 'the robot', robot, 'robot')
    pid = graph.node_pid('/fake_turtlebot')
    master = xmlrpc.client.ServerProxy(graph.env['ROS_MASTER_URI'])
    uri = master.lookupNode('/test', '/fake_turtlebot')[2]
    # What a calibrate_linear that ended without unregistering leaves on
    # the master when the robot has been given its port since; then a new
    # calibrate_linear starts: the master sends the old one's address a
    # shutdown naming /calibrate_linear.
    master.registerPublisher('/calibrate_linear', '/stale', 'std_msgs/String', uri)
    master.registerPublisher('/calibrate_linear', '/stale', 'std_msgs/String',
                             'http://localhost:9/')
    graph.wait_for(lambda: robot.poll() is not None or any(
        line in graph.output('robot') for line in ('refused, this node goes on',
                                                   'shutdown request')), 'the request',
                   robot, 'robot')
    assert robot.poll() is None, graph.output('robot')
    assert 'refused, this node goes on' in graph.output('robot')
    assert graph.node_pid('/fake_turtlebot') == pid  # and it answers

    # The same request naming the robot is obeyed: it ends.
    master.registerPublisher('/fake_turtlebot', '/stale', 'std_msgs/String',
                             'http://localhost:9/')
    try:
        robot.wait(HANG_GUARD)
    except subprocess.TimeoutExpired:
        pytest.fail('the robot did not end:\n' + graph.output('robot'))
    assert 'new node registered with same name' in graph.output('robot')
