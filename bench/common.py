"""What the bench tools share: the repository's paths, processes and their
CPU from /proc, a simulator's ground truth, a log line, a table cell.

Starting and ending processes, and waiting for a master, are the test
suite's own (test/helpers/master.py), and a ground-truth pose is read by
its echo (test/helpers/truth_echo.py): bench and tests start graphs the
same way.
"""
import os
import select
import socket
import subprocess
import sys

BENCH = os.path.dirname(os.path.abspath(__file__))
#: The repository, links resolved (a workspace's src/ links to it).
ROOT = os.path.dirname(os.path.realpath(BENCH))
RESULTS = os.path.join(BENCH, 'results')
HELPERS = os.path.join(ROOT, 'test', 'helpers')
if HELPERS not in sys.path:
    sys.path.append(HELPERS)
from master import end_processes, wait_for_master  # noqa: E402,F401

TRUTH_ECHO = os.path.join(HELPERS, 'truth_echo.py')


def free_port():
    with socket.socket() as s:
        s.bind(('localhost', 0))
        return s.getsockname()[1]


def stat_cpu(path):
    """User + system CPU seconds of a process or thread from its /proc stat
    file ``path``; None if gone."""
    try:
        with open(path) as f:
            fields = f.read().rsplit(')', 1)[1].split()
    except OSError:
        return None
    return (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')


def cpu_seconds(pid):
    """User + system CPU seconds of a process, from /proc; None if gone."""
    return stat_cpu('/proc/%d/stat' % pid)


def descendants(pid):
    """{pid: command line} of every process below ``pid``."""
    children = {}
    for entry in os.listdir('/proc'):
        if not entry.isdigit():
            continue
        try:
            with open('/proc/%s/stat' % entry) as f:
                ppid = int(f.read().rsplit(')', 1)[1].split()[1])
            children.setdefault(ppid, []).append(int(entry))
        except (OSError, ValueError, IndexError):
            continue
    found, todo = {}, [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            try:
                with open('/proc/%d/cmdline' % child, 'rb') as f:
                    found[child] = f.read().replace(b'\0', b' ').decode(errors='replace')
            except OSError:
                continue
            todo.append(child)
    return found


def node_name(cmdline):
    """The name a process of a graph goes by, from its command line: its
    ``__name:=``, rosmaster, roscore, or its script's; None for the rest
    (roslaunch, a shell)."""
    argv = cmdline.split()
    names = [a.split(':=', 1)[1] for a in argv if a.startswith('__name:=')]
    if names:
        return names[0]
    if any(a.endswith('rosmaster') for a in argv):
        return 'rosmaster'
    if any(a.endswith('roscore') for a in argv[:3]):
        return 'roscore (roslaunch)'
    scripts = [os.path.basename(a)[:-3] for a in argv[:3] if a.endswith('.py')]
    return scripts[0] if scripts else None


def processes(root):
    """{pid: node name} of ``root`` and its descendants (roslaunch puts
    each node in a session of its own, so process groups do not do)."""
    family = descendants(root)
    try:
        with open('/proc/%d/cmdline' % root, 'rb') as f:
            family[root] = f.read().replace(b'\0', b' ').decode(errors='replace')
    except OSError:
        pass
    return {pid: node_name(cmdline) for pid, cmdline in family.items()
            if node_name(cmdline)}


def cpu_by_name(names):
    """{name: CPU seconds so far} of the processes ``names`` ({pid: name};
    one named None is left out)."""
    totals = {}
    for pid, name in names.items():
        if name is not None:
            totals[name] = totals.get(name, 0.0) + (cpu_seconds(pid) or 0.0)
    return totals


def ground_truth(env, topic='ground_truth', wall_limit=30.0):
    """(x, y, yaw) of the simulator's next message on ``topic``, on the
    master of ``env``: the first line truth_echo.py prints."""
    proc = subprocess.Popen([sys.executable, TRUTH_ECHO, '--topic', topic], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                            universal_newlines=True, start_new_session=True)
    try:
        ready = select.select([proc.stdout], [], [], wall_limit)[0]
        line = proc.stdout.readline() if ready else ''
    finally:
        end_processes([proc], 5)
    if not line:
        raise RuntimeError('no %s within %.0f s' % (topic, wall_limit))
    return tuple(float(value) for value in line.split()[1:])


def log(text):
    sys.stderr.write(text + '\n')
    sys.stderr.flush()


def fmt(value, spec='%.1f'):
    """A table cell: ``value`` as ``spec`` says, '-' if None."""
    return '-' if value is None else spec % value
