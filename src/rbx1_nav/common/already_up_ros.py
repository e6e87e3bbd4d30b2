"""Look before registering: is a node of this name already running?
(the logic and lines: rbx1_nav.common.already_up).

The master shuts a node down when another registers under its name, so
these checks run before ``rospy.init_node``, through the master's XML-RPC
API only, each call with a socket timeout: a name counts as taken when
its node answers; a registration left by a killed node does not answer
and does not count.
"""
import os
import signal
import sys
import xmlrpc.client

import rosgraph

from rbx1_nav.common import launch_end
from rbx1_nav.common.already_up import refusal_text, resolved_name, skip_text
from rbx1_nav.common.master_watch import proxy

__all__ = ['running_pid', 'refuse_if_running', 'running_already', 'exec_unless_running',
           'unless_running']

CALLER = '/rbx1_nav_already_up'


def _call(uri, method, *args):
    """The value of the XML-RPC call ``method(CALLER, *args)`` at ``uri``;
    None if it fails or does not answer within TIMEOUT."""
    try:
        code, _, value = getattr(proxy(uri), method)(CALLER, *args)
    except (OSError, xmlrpc.client.Error, ValueError):
        return None
    return value if code == 1 else None


def running_pid(name, master_uri=None):
    """The process id of the running node registered as ``name``, or None."""
    uri = _call(master_uri or rosgraph.get_master_uri(), 'lookupNode', name)
    return None if uri is None else _call(uri, 'getPid')


def _clock_running(master_uri, launch):
    """True if a running node publishes /clock, other than one started by
    this node's own roslaunch (process ``launch``: the refused launch's
    sim_clock, starting beside this node); None if the master does not
    answer."""
    state = _call(master_uri, 'getSystemState')
    if state is None:
        return None
    procs = launch_end.processes()
    for topic, nodes in state[0]:
        if topic == '/clock':
            pids = [running_pid(node, master_uri) for node in nodes]
            return any(pid is not None and procs.get(pid, (None,))[0] != launch
                       for pid in pids)
    return False


def _holder(default, argv=None, environ=None):
    """(name, pid) of the running node that holds this node's name (``default``,
    or its ``__name:=``); None if none does, or for --help."""
    argv = sys.argv if argv is None else argv
    environ = os.environ if environ is None else environ
    if {'-h', '--help'} & set(argv[1:]):
        return None
    name = resolved_name(argv, environ.get('ROS_NAMESPACE', ''), default)
    pid = running_pid(name)
    return None if pid is None or pid == os.getpid() else (name, pid)


def refuse_if_running(default, argv=None, environ=None):
    """If this node's name (``default``, or its ``__name:=``) is held by a
    running node: print the refusal, put back /use_sim_time as the running
    graph needs it (this launch has just set it), end this roslaunch the
    way Ctrl-C does, and return True. Otherwise False."""
    held = _holder(default, argv, environ)
    if held is None:
        return False
    print('[ERROR] %s: %s' % (default, refusal_text(*held)), flush=True)
    master_uri = rosgraph.get_master_uri()
    parent = os.getppid()
    clock = _clock_running(master_uri, parent)
    if clock is not None:
        _call(master_uri, 'setParam', '/use_sim_time', clock)
    procs = launch_end.processes()
    if parent in procs and launch_end.is_roslaunch(procs[parent][1]):
        # roslaunch's SIGINT back to this process as it ends: this node is
        # on its way out already.
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        os.kill(parent, signal.SIGINT)
    return True


def running_already(default, argv=None, environ=None):
    """True, having printed so, if a running node holds this node's name
    (``default``, or its ``__name:=``): a second launch's node is then to
    leave it alone (sim_clock.py; another program: unless_running.py)."""
    held = _holder(default, argv, environ)
    if held is not None:
        print('[WARN] %s' % skip_text(*held), flush=True)
    return held is not None


def exec_unless_running(argv, environ=None):
    """nodes/unless_running.py: ``argv`` is PKG TYPE ARGS... (roslaunch
    adds ``__name:=``). Run the node roslaunch would start for PKG's TYPE
    (exec, so roslaunch's signals reach it) unless a running node holds its
    name; then print why not and return 0. None for a usage error, 1 for a
    node that is not there."""
    if len(argv) < 2 or argv[0] in ('-h', '--help'):
        return None
    import roslib.packages
    found = roslib.packages.find_node(argv[0], argv[1])
    if not found:
        print('[ERROR] unless_running.py: package %s has no node %s (is it built, '
              'and its workspace sourced?)' % (argv[0], argv[1]), flush=True)
        return 1
    argv = [found[0]] + argv[2:]
    environ = os.environ if environ is None else environ
    name = resolved_name(argv, environ.get('ROS_NAMESPACE', ''),
                         os.path.basename(argv[0]))
    pid = running_pid(name)
    if pid is not None:
        print('[WARN] %s' % skip_text(name, pid), flush=True)
        return 0
    os.execvp(argv[0], argv)


def unless_running(argv, doc):
    """nodes/unless_running.py's main(): :func:`exec_unless_running`, or its
    usage (``doc``) on a usage error; the exit status (0 for --help, else 2)."""
    status = exec_unless_running(argv)
    if status is None:
        print(doc.strip())
        status = 0 if argv[:1] in (['-h'], ['--help']) else 2
    return status
