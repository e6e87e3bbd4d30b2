"""A subscriber that stops reading does not stop the fake robot.

The robot writes each message before publish() returns (no queue thread
per subscriber: rbx1_nav.sim.topics_ros.UnheldPublisher), so a subscriber
that never reads (a terminal paused with Ctrl-Z) would, once the kernel's
buffers are full, hold every later publish: every other subscriber's
odometry would stop with it. Here one subscriber connects to /odom with a
small receive buffer and never reads, another reads on: the reader's
stream goes on, with no gap longer than the write's limit (STALL) and a
little, and the robot drops the stalled connection (it reads its end). The
robot runs at 20x simulated time, so the buffers fill in seconds.

Both subscribers speak TCPROS from this process (no node: rostopic would
read). Its own roscore on a free port; every process it started is ended.
"""
import os
import shutil
import socket
import struct
import subprocess
import sys
import threading
import time
import xmlrpc.client

import pytest
from nav_msgs.msg import Odometry

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'helpers'))
from master import end_processes, wait_for_master  # noqa: E402
from ports import free_port  # noqa: E402

from rbx1_nav.sim.topics_ros import STALL  # noqa: E402

pytestmark = pytest.mark.skipif(
    not shutil.which('roslaunch') or 'ROS_PACKAGE_PATH' not in os.environ,
    reason='needs a sourced ROS workspace (make test sources one)')

PORTS = range(11512, 11516)
SPEED = 20  # simulated time at 20x: 1000 odometry messages a wall s fill the buffers in seconds
LIMIT = 90.0  # wall s for the robot to drop the stalled subscriber (kernel buffers of 4 MB: ~6 s)
GAP = STALL + 1.0  # wall s the reader's stream may pause (a write held STALL s, then a catch-up)


def _header(fields):
    """A TCPROS connection header: each field length-prefixed, and the whole."""
    body = b''
    for key, value in fields.items():
        field = ('%s=%s' % (key, value)).encode()
        body += struct.pack('<I', len(field)) + field
    return struct.pack('<I', len(body)) + body


def _read_exactly(sock, n):
    data = b''
    while len(data) < n:
        chunk = sock.recv(n - len(data))
        if not chunk:
            raise EOFError('closed')
        data += chunk
    return data


def subscribe(address, name, receive_buffer=None):
    """A TCPROS connection to the robot's /odom, its header read."""
    sock = socket.socket()
    if receive_buffer:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, receive_buffer)
    sock.connect(address)
    sock.sendall(_header({'callerid': name, 'topic': '/odom', 'md5sum': Odometry._md5sum,
                          'type': Odometry._type, 'tcp_nodelay': '1'}))
    length, = struct.unpack('<I', _read_exactly(sock, 4))
    _read_exactly(sock, length)
    return sock


def connected(node_uri, name):
    """True while ``name`` is among the node's connections (getBusInfo)."""
    code, _, bus = xmlrpc.client.ServerProxy(node_uri).getBusInfo('/test')
    return code == 1 and any(row[1] == name for row in bus)


def test_a_subscriber_that_stops_reading_does_not_stop_the_robot(tmp_path):
    port = free_port(PORTS)
    env = dict(os.environ, ROS_MASTER_URI='http://localhost:%d' % port,
               ROS_LOG_DIR=str(tmp_path))
    procs = []
    try:
        procs.append(subprocess.Popen(['roscore', '-p', str(port)], env=env,
                                      stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT,
                                      start_new_session=True))
        wait_for_master(env['ROS_MASTER_URI'], procs[0])
        robot = subprocess.Popen(['roslaunch', 'rbx1_nav', 'fake_turtlebot.launch',
                                  'sim_speed:=%d' % SPEED, 'lockstep:=false', 'model:=false'],
                                 env=env, stdout=open(str(tmp_path / 'robot.log'), 'w'),
                                 stderr=subprocess.STDOUT, start_new_session=True)
        procs.append(robot)
        master = xmlrpc.client.ServerProxy(env['ROS_MASTER_URI'])
        deadline = time.monotonic() + 60.0
        while True:
            code, _, uri = master.lookupNode('/test', '/fake_turtlebot')
            if code == 1:
                code, _, proto = xmlrpc.client.ServerProxy(uri).requestTopic(
                    '/test', '/odom', [['TCPROS']])
                if code == 1:
                    break
            assert robot.poll() is None and time.monotonic() < deadline, 'no robot'
            time.sleep(0.2)
        address = (proto[1], proto[2])
        stalled = subscribe(address, '/stalled', receive_buffer=4096)  # never read
        reader = subscribe(address, '/reader')
        arrivals, done = [], threading.Event()

        def read():
            while not done.is_set():
                length, = struct.unpack('<I', _read_exactly(reader, 4))
                _read_exactly(reader, length)
                arrivals.append(time.monotonic())
        started = time.monotonic()
        thread = threading.Thread(target=read, daemon=True)
        thread.start()
        while connected(uri, '/stalled') and time.monotonic() < started + LIMIT:
            time.sleep(0.5)
        dropped = time.monotonic() - started
        done.set()
        thread.join(10.0)
        assert not thread.is_alive(), 'the reader\'s stream stopped: %d messages' % len(arrivals)
        gaps = [b - a for a, b in zip([started] + arrivals, arrivals)]
        print('stalled subscriber dropped after %.1f s; the reader: %d messages, longest gap '
              '%.2f s' % (dropped, len(arrivals), max(gaps)))
        assert dropped < LIMIT, 'the stalled subscriber is still connected'
        assert len(arrivals) >= 0.5 * 50 * SPEED * dropped  # the robot's 50 Hz, at 20x
        assert max(gaps) < GAP
        # The robot closed its end: what the stalled socket holds ends in EOF.
        stalled.settimeout(10.0)
        with pytest.raises((EOFError, ConnectionResetError)):
            while True:
                _read_exactly(stalled, 65536)
        assert robot.poll() is None
    finally:
        end_processes(procs, 10)
