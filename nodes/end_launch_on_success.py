#!/usr/bin/env python3
"""end_launch_on_success: run a node; when it exits with status 0, end the
roslaunch that started it the way Ctrl-C does.

Without it, roslaunch ends a launch whose required node has finished with
a red "REQUIRED process [...] has died! ... Initiating shutdown!" block,
even after a successful course. As a node's launch-prefix:

  <node ... required="true" launch-prefix="rosrun rbx1_nav end_launch_on_success.py">

A node that fails (non-zero status) still ends a launch with the red block
naming its exit code. Under rostest, or with other wrapped nodes of the
launch still running (a fleet's courses), the wrapper exits with the
node's status and leaves the launch alone. See rbx1_nav.common.launch_end.
"""
import os
import signal
import subprocess
import sys
import time

from rbx1_nav.common import launch_end


def main(argv):
    if not argv or argv[0] in ('-h', '--help'):
        print(__doc__.strip())
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
    procs = launch_end.processes()
    if (parent not in procs or not launch_end.is_roslaunch(procs[parent][1])
            or launch_end.others_running(os.getpid(), procs)):
        return 0
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, lambda signum, frame: os._exit(0))
    print('[%s] finished cleanly: ending the launch'
          % launch_end.node_name(argv, os.environ.get('ROS_NAMESPACE', '')),
          flush=True)
    os.kill(parent, signal.SIGINT)
    # roslaunch stops its nodes, this one among them; should it be gone
    # without doing so, end anyway.
    while os.getppid() == parent:
        time.sleep(0.2)
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
