"""When a node's clean exit may end the roslaunch that started it
(nodes/end_launch_on_success.py). No rospy here.

roslaunch announces the end of a required node, whatever its exit status,
with a red "REQUIRED process [...] has died! ... Initiating shutdown!"
block, which after a successful course looks like a failure. The wrapper
runs the node and, when it exits with status 0, sends roslaunch the SIGINT
of a Ctrl-C instead: roslaunch then stops the other nodes and exits 0
without the block. Only a roslaunch parent gets the signal (rostest, which
runs the same launch files, reports a required node's end its own way),
and only once no other wrapped node of the same launch is still running
(a fleet's courses end the launch when the last one is done).
"""
import os
import signal
import subprocess
import time

__all__ = ['is_roslaunch', 'others_running', 'processes', 'node_name', 'run']

SCRIPT = 'end_launch_on_success.py'


def is_roslaunch(argv):
    """True if ``argv`` (a command line) is roslaunch's main process: not
    rostest, and not a remote machine's ``roslaunch --child`` server."""
    return (any(os.path.basename(arg) == 'roslaunch' for arg in argv[:2])
            and '--child' not in argv)


def _is_wrapper(argv):
    return any(os.path.basename(arg) == SCRIPT for arg in argv[:2])


def others_running(me, procs):
    """True if another wrapper started by the same parent as ``me`` still
    runs its node. ``procs`` is {pid: (parent pid, argv)}, as from
    :func:`processes`."""
    parent = procs[me][0]
    wrappers = [pid for pid, (ppid, argv) in procs.items()
                if ppid == parent and pid != me and _is_wrapper(argv)]
    return any(ppid in wrappers for ppid, _ in procs.values())


def processes(root='/proc'):
    """{pid: (parent pid, argv)} of the processes under ``root`` (Linux
    /proc); processes that end while it reads are left out."""
    found = {}
    for entry in os.listdir(root):
        if not entry.isdigit():
            continue
        try:
            with open(os.path.join(root, entry, 'stat')) as f:
                ppid = int(f.read().rsplit(')', 1)[1].split()[1])
            with open(os.path.join(root, entry, 'cmdline'), 'rb') as f:
                argv = f.read().decode(errors='replace').split('\0')[:-1]
        except (OSError, ValueError, IndexError):
            continue
        found[int(entry)] = (ppid, argv)
    return found


def node_name(argv, namespace=''):
    """The node's name as roslaunch shows it (``robot2/odom_out_and_back``)
    from its ``__name:=`` argument and ``namespace`` (the ROS_NAMESPACE
    roslaunch gives it), else the program's file name."""
    name = os.path.basename(argv[0]) if argv else ''
    for arg in argv:
        if arg.startswith('__name:='):
            name = arg[len('__name:='):]
    return '/'.join(part for part in (namespace.strip('/'), name) if part)


def run(argv, doc):
    """Run the node ``argv``; once it exits 0, end the roslaunch that
    started it as Ctrl-C does (see the module docstring). Its exit status."""
    if not argv or argv[0] in ('-h', '--help'):
        print(doc.strip())
        return 0 if argv else 2
    node = subprocess.Popen(argv)
    signalled = []

    def forward(signum, frame):
        signalled.append(signum)
        node.send_signal(signum)
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, forward)
    status = node.wait()
    if status != 0 or signalled:  # failed, or stopped by Ctrl-C / roslaunch
        return status if status >= 0 else 128 - status
    parent = os.getppid()
    procs = processes()
    if (parent not in procs or not is_roslaunch(procs[parent][1])
            or others_running(os.getpid(), procs)):
        return 0
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, lambda signum, frame: os._exit(0))
    print('[%s] finished cleanly: ending the launch'
          % node_name(argv, os.environ.get('ROS_NAMESPACE', '')),
          flush=True)
    os.kill(parent, signal.SIGINT)
    # roslaunch stops its nodes, this one among them; should it be gone
    # without doing so, end anyway.
    while os.getppid() == parent:
        time.sleep(0.2)
    return 0
