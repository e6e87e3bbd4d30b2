"""Two hosts on one machine, joined by a link the test can slow, thin or cut.

``TwoHosts`` makes two network namespaces, ``robot`` (10.231.0.1: the
master, the driver or simulator) and ``workstation`` (10.231.0.2: the
course), each with a TUN device, and runs a relay between the two TUN
devices: every IP packet from one host goes through the relay to the
other. ``tc netem`` is not in these kernels, so the relay is the link:
``set(delay=0.2)`` holds each packet 200 ms, ``set(loss=0.2)`` drops one
in five, ``set(loss=1.0)`` cuts it, ``set(loss=1.0, towards='robot')``
cuts the way to the robot only. ``run(host, argv)`` starts a process on
a host with ROS_IP and ROS_MASTER_URI set for it.

Run as a script, this module is the relay itself (``python3 link.py
CONTROL_FILE``): it opens the TUN devices, then reads delay and loss from
CONTROL_FILE whenever that changes.
"""
import ctypes
import fcntl
import heapq
import json
import os
import random
import select
import shutil
import struct
import subprocess
import sys
import tempfile
import time

ADDRESSES = {'robot': '10.231.0.1', 'workstation': '10.231.0.2'}
MASTER_PORT = 11311
TUNSETIFF = 0x400454ca
IFF_TUN, IFF_NO_PI = 0x0001, 0x1000
CLONE_NEWNET = 0x40000000


def unavailable():
    """Why two hosts cannot be made here, or None."""
    if os.geteuid() != 0:
        return 'network namespaces need root'
    if not os.path.exists('/dev/net/tun'):
        return 'no /dev/net/tun'
    if not shutil.which('ip'):
        return 'no ip command (iproute2)'
    return None


def _open_tun(netns):
    """A TUN device named tun0 inside network namespace ``netns``."""
    libc = ctypes.CDLL(None, use_errno=True)
    with open('/proc/self/ns/net') as home, open('/run/netns/' + netns) as there:
        if libc.setns(there.fileno(), CLONE_NEWNET) != 0:
            raise OSError(ctypes.get_errno(), 'setns ' + netns)
        try:
            fd = os.open('/dev/net/tun', os.O_RDWR)
            fcntl.ioctl(fd, TUNSETIFF, struct.pack('16sH', b'tun0', IFF_TUN | IFF_NO_PI))
        finally:
            libc.setns(home.fileno(), CLONE_NEWNET)
    return fd


def relay(control, names):
    """Forward packets between the two namespaces' TUN devices forever."""
    fds = [_open_tun(name) for name in names]
    other = {fds[0]: fds[1], fds[1]: fds[0]}
    host = dict(zip(fds, ADDRESSES))  # the devices' order is ADDRESSES's
    settings, mtime = {'delay': 0.0, 'loss': 0.0, 'towards': None}, None
    queue, order = [], 0  # (due, order, fd, packet)
    sys.stdout.write('ready\n')
    sys.stdout.flush()
    while True:
        try:
            stamp = os.stat(control).st_mtime_ns
            if stamp != mtime:
                with open(control) as f:
                    settings.update(json.load(f))
                mtime = stamp
        except (OSError, ValueError):
            pass
        now = time.monotonic()
        while queue and queue[0][0] <= now:
            _, _, fd, packet = heapq.heappop(queue)
            try:
                os.write(fd, packet)
            except OSError:  # the device is down (set-up, tear-down): lost
                pass
        timeout = min(0.005, max(0.0, queue[0][0] - now)) if queue else 0.005
        ready, _, _ = select.select(fds, [], [], timeout)
        for fd in ready:
            packet = os.read(fd, 65536)
            if (settings['towards'] in (None, host[other[fd]])
                    and random.random() < settings['loss']):
                continue
            order += 1
            heapq.heappush(queue, (time.monotonic() + settings['delay'], order,
                                   other[fd], packet))


def kill_tree(pid, sig=9):
    """Send ``sig`` to ``pid`` and all its descendants (roslaunch starts
    the master and rosout in sessions of their own, out of its group)."""
    parents = {}
    for entry in os.listdir('/proc'):
        if entry.isdigit():
            try:
                with open('/proc/%s/stat' % entry) as f:
                    parents[int(entry)] = int(f.read().rsplit(')', 1)[1].split()[1])
            except OSError:
                pass
    tree, grew = {pid}, True
    while grew:
        more = {p for p, parent in parents.items() if parent in tree} - tree
        tree |= more
        grew = bool(more)
    for member in tree:
        try:
            os.kill(member, sig)
        except ProcessLookupError:
            pass


class TwoHosts(object):
    """The robot and the workstation, and the link between them."""

    def __init__(self):
        tag = '%d' % os.getpid()
        self.ns = {host: 'rbx%s%s' % (host[0], tag) for host in ADDRESSES}
        self.dir = tempfile.mkdtemp(prefix='rbx1_link_')
        self.control = os.path.join(self.dir, 'link.json')
        self.procs = []
        self.relay = None
        self.set()
        try:
            self._make()
        except Exception:
            self.close()
            raise
        self.master_uri = 'http://%s:%d' % (ADDRESSES['robot'], MASTER_PORT)

    def _make(self):
        self.relay = None
        for ns in self.ns.values():
            subprocess.check_call(['ip', 'netns', 'add', ns])
        self.relay = subprocess.Popen(
            [sys.executable, os.path.abspath(__file__), self.control,
             self.ns['robot'], self.ns['workstation']],
            stdout=subprocess.PIPE, universal_newlines=True)
        if self.relay.stdout.readline().strip() != 'ready':
            raise RuntimeError('the link relay did not start')
        for host, ns in self.ns.items():
            peer = ADDRESSES['workstation' if host == 'robot' else 'robot']
            for cmd in (['ip', 'link', 'set', 'lo', 'up'],
                        ['ip', 'addr', 'add', ADDRESSES[host], 'peer', peer, 'dev', 'tun0'],
                        ['ip', 'link', 'set', 'tun0', 'up']):
                subprocess.check_call(['ip', 'netns', 'exec', ns] + cmd)

    def set(self, delay=0.0, loss=0.0, towards=None):
        """Change the link: one-way ``delay`` (s) and ``loss`` (0..1), the
        loss of the packets to one host only when ``towards`` names it."""
        tmp = self.control + '.tmp'
        with open(tmp, 'w') as f:
            json.dump({'delay': delay, 'loss': loss, 'towards': towards}, f)
        os.replace(tmp, self.control)

    def run(self, host, argv, ros_env=True, **popen):
        """Start ``argv`` on ``host`` with its ROS_IP and the master's URI
        (with ``ros_env`` false, with neither: ``argv`` sets them)."""
        env = dict(os.environ, ROS_IP=ADDRESSES[host], ROS_MASTER_URI=self.master_uri,
                   PYTHONUNBUFFERED='1')
        env.pop('ROS_HOSTNAME', None)
        if not ros_env:
            del env['ROS_IP'], env['ROS_MASTER_URI']
        proc = subprocess.Popen(['ip', 'netns', 'exec', self.ns[host]] + list(argv),
                                env=env, start_new_session=True, **popen)
        self.procs.append(proc)
        return proc

    def close(self):
        for proc in reversed(self.procs):
            kill_tree(proc.pid)
            proc.wait()
        if self.relay is not None and self.relay.poll() is None:
            self.relay.kill()
            self.relay.wait()
        for ns in self.ns.values():
            subprocess.call(['ip', 'netns', 'del', ns], stderr=subprocess.DEVNULL)
        shutil.rmtree(self.dir, ignore_errors=True)


if __name__ == '__main__':
    relay(sys.argv[1], sys.argv[2:4])
