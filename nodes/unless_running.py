#!/usr/bin/env python3
"""unless_running: start a node unless a running node already holds its name.

As a node's launch-prefix:

  <node ... launch-prefix="rosrun rbx1_nav unless_running.py">

A second fake_turtlebot.launch would otherwise shut down the running
robot's robot_state_publisher, sim_clock and RViz (the master shuts a node
down when another registers under its name). With a running node of that
name it prints so and exits 0; otherwise it becomes the node (exec). See
rbx1_nav.sim.already_up.
"""
import signal
import sys

# Ctrl-C (or the launch ending) before the node starts: end quietly.
signal.signal(signal.SIGINT, signal.SIG_DFL)

from rbx1_nav.sim.already_up_ros import exec_unless_running  # noqa: E402

if __name__ == '__main__':
    status = exec_unless_running(sys.argv[1:])
    if status is None:
        print(__doc__.strip())
        status = 0 if sys.argv[1:] else 2
    sys.exit(status)
