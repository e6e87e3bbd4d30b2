"""Waiting for a test's own master, and asking it for a node (imported,
not a node)."""
import os
import signal
import subprocess
import time
import xmlrpc.client

import rosgraph

#: Wall seconds: a hang guard, never a verdict. A master that is starting
#: is waited for as long as its process lives, however loaded the machine.
HANG_GUARD = 300.0


def wait_for_master(uri, roscore, output=lambda: ''):
    """Until the master at ``uri`` answers; fail at once, with ``output()``,
    if ``roscore`` (its Popen) has ended, or after HANG_GUARD s alive.
    Returns the wall seconds it took."""
    started = time.monotonic()
    while not rosgraph.is_master_online(uri):
        assert roscore.poll() is None, 'roscore ended (exit %s) before its master answered:\n%s' % (
            roscore.returncode, output())
        assert time.monotonic() - started < HANG_GUARD, (
            'roscore alive but no master at %s after %.0f s:\n%s' % (uri, HANG_GUARD, output()))
        time.sleep(0.05)
    return time.monotonic() - started


def node_pid(master, name):
    """The process id node ``name`` gives when asked (``rosnode info``'s
    Pid, and ``rosnode ping``'s question): it answers. ``master``: a
    rosgraph.Master."""
    node = xmlrpc.client.ServerProxy(master.lookupNode(name))
    code, message, pid = node.getPid(master.caller_id)
    assert code == 1, (name, message)
    return pid


def end_processes(procs, wait):
    """End the process groups of ``procs`` (Popen, started with a session of their own), the last
    started first: SIGINT, as Ctrl-C, then SIGKILL to any not gone in ``wait`` s."""
    for proc in reversed(procs):
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGINT)
    for proc in reversed(procs):
        try:
            proc.wait(wait)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
