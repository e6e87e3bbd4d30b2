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

Under roslaunch the wrapper also, once its node has ended (any status):
removes the node's private parameters from the master (``forget``), so
that the values the launch gave it (a scaled ~start_delay, precise:=true)
do not stay behind for a later rosrun of the same node; and, when
nodes/launch_status.py started the launch, writes the node's status where
that program finds it: roslaunch exits 0 even when a required node failed,
launch_status.py exits with the course's status (:func:`launch_status`).

A launch with simulated time sets the global /use_sim_time (and /lockstep),
which roslaunch also leaves on the master: a later rosrun would wait for a
/clock that no longer comes. The launch's clock removes them as it ends
(:func:`sim_time_to_clear`): sim_clock.py, or this wrapper around
``rosbag play --clock``.
"""
import os
import signal
import subprocess
import tempfile
import time

__all__ = ['is_roslaunch', 'others_running', 'processes', 'node_name', 'run',
           'record_status', 'read_statuses', 'launch_status', 'run_launch',
           'STATUS_DIR', 'SIM_TIME_PARAMS', 'sim_time_to_clear', 'parent_is_roslaunch',
           'publishes_clock']

SCRIPT = 'end_launch_on_success.py'
#: The environment variable that tells wrapped nodes where to record their
#: exit status (set by :func:`run_launch`).
STATUS_DIR = 'RBX1_NAV_STATUS_DIR'


def is_roslaunch(argv):
    """True if ``argv`` (a command line) is roslaunch's main process: not
    rostest, and not a remote machine's ``roslaunch --child`` server."""
    return (any(os.path.basename(arg) == 'roslaunch' for arg in argv[:2])
            and '--child' not in argv)


def _is_wrapper(argv):
    return any(os.path.basename(arg) == SCRIPT for arg in argv[:2])


#: The global parameters a launch's simulated time sets (sim_clock.launch,
#: pose_ekf_replay.launch), for the nodes of the launch.
SIM_TIME_PARAMS = ('/use_sim_time', '/lockstep')


def sim_time_to_clear(launch_clock, other_clocks):
    """The SIM_TIME_PARAMS to remove as a clock ends: all of them if it was
    its roslaunch's clock (``launch_clock``), unless ``other_clocks``
    (other running nodes publishing /clock: a bag played with --clock, a
    sim_clock started by hand) still serve nodes that read them as they
    start; else none. Absent, every node reads /use_sim_time as false."""
    return SIM_TIME_PARAMS if launch_clock and not other_clocks else ()


def parent_is_roslaunch(root='/proc'):
    """True if this process's parent is roslaunch's main process (not
    rostest, whose graph ends with its own master)."""
    try:
        with open(os.path.join(root, str(os.getppid()), 'cmdline'), 'rb') as f:
            argv = f.read().decode(errors='replace').split('\0')[:-1]
    except OSError:
        return False
    return is_roslaunch(argv)


def publishes_clock(argv):
    """True if the command line ``argv`` is a node that publishes /clock
    (``rosbag play --clock``)."""
    return '--clock' in argv[1:]


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


def record_status(directory, name, status):
    """Note that node ``name`` ended with ``status``, in ``directory``
    (one file per wrapper; :func:`read_statuses` reads them)."""
    path = os.path.join(directory, '%d.status' % os.getpid())
    with open(path + '.tmp', 'w') as f:
        f.write('%d %s\n' % (status, name))
    os.rename(path + '.tmp', path)


def read_statuses(directory):
    """[(status, node name)] of the wrapped nodes that ended, in the order
    they ended."""
    found = []
    for entry in os.listdir(directory):
        if not entry.endswith('.status'):
            continue
        path = os.path.join(directory, entry)
        try:
            with open(path) as f:
                status, name = f.read().split(None, 1)
            found.append((os.path.getmtime(path), int(status), name.strip()))
        except (OSError, ValueError):
            continue
    return [(status, name) for _, status, name in sorted(found)]


def launch_status(statuses, roslaunch_status):
    """(exit status, line) of a launch run by launch_status.py: the first
    course (wrapped node) to fail, else roslaunch's own failure, else 0.
    ``statuses`` as from :func:`read_statuses`."""
    failed = [(status, name) for status, name in statuses if status != 0]
    if failed:
        status, name = failed[0]
        return status, ('launch_status: %s exited %d; exiting %d'
                        % (name, status, status))
    if roslaunch_status != 0:
        return roslaunch_status, ('launch_status: roslaunch exited %d'
                                  % roslaunch_status)
    if statuses:
        return 0, ('launch_status: %s exited 0'
                   % ', '.join(name for _, name in statuses))
    return 0, 'launch_status: roslaunch exited 0 (no course in the launch)'


def run_launch(args, doc):
    """nodes/launch_status.py: ``roslaunch args``, then exit with the
    status of :func:`launch_status`. Ctrl-C reaches roslaunch (the same
    terminal); this process only waits for it."""
    if not args or args[0] in ('-h', '--help'):
        print(doc.strip())
        return 0 if args else 2
    directory = tempfile.mkdtemp(prefix='rbx1_nav_status_')
    try:
        env = dict(os.environ, **{STATUS_DIR: directory})
        launch = subprocess.Popen(['roslaunch'] + list(args), env=env)
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        signal.signal(signal.SIGTERM,
                      lambda signum, frame: launch.send_signal(signum))
        roslaunch_status = launch.wait()
        if roslaunch_status < 0:
            roslaunch_status = 128 - roslaunch_status
        status, line = launch_status(read_statuses(directory), roslaunch_status)
    finally:
        for entry in os.listdir(directory):
            os.unlink(os.path.join(directory, entry))
        os.rmdir(directory)
    print(line, flush=True)
    return status


def run(argv, doc, forget=None, end_clock=None):
    """Run the node ``argv``; once it exits 0, end the roslaunch that
    started it as Ctrl-C does (see the module docstring). Its exit status.

    ``forget(name)``, under roslaunch, removes the ended node's private
    parameters (the global name ``name``) from the master; ``end_clock()``,
    under roslaunch, after a node that published /clock, removes what
    :func:`sim_time_to_clear` says."""
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
    if status < 0:
        status = 128 - status
    parent = os.getppid()
    procs = processes()
    under_roslaunch = parent in procs and is_roslaunch(procs[parent][1])
    name = node_name(argv, os.environ.get('ROS_NAMESPACE', ''))
    if under_roslaunch:
        if forget:
            forget('/' + name)
        if end_clock and publishes_clock(argv):
            end_clock()
        if os.environ.get(STATUS_DIR):
            try:
                record_status(os.environ[STATUS_DIR], name, status)
            except OSError:
                pass
    if status != 0 or signalled:  # failed, or stopped by Ctrl-C / roslaunch
        return status
    if not under_roslaunch or others_running(os.getpid(), procs):
        return 0
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, lambda signum, frame: os._exit(0))
    print('[%s] finished cleanly: ending the launch' % name, flush=True)
    os.kill(parent, signal.SIGINT)
    # roslaunch stops its nodes, this one among them; should it be gone
    # without doing so, end anyway.
    while os.getppid() == parent:
        time.sleep(0.2)
    return 0
