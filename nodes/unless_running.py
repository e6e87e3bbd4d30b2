#!/usr/bin/env python3
"""unless_running: start a node unless a running node already holds its name.

As the node, the real node's package and type first in its args:

  <node pkg="rbx1_nav" type="unless_running.py" name="robot_state_publisher"
        args="robot_state_publisher robot_state_publisher"/>

A second fake_turtlebot.launch would otherwise shut down the running
robot's robot_state_publisher, sim_clock and RViz (the master shuts a node
down when another registers under its name). With a running node of that
name it prints so and exits 0; otherwise it becomes the node (exec). The
node, not a launch-prefix run through rosrun: rosrun's package search
costs half a CPU second at each start (every rostest starts two), and
roslaunch finds a node in its own process. See rbx1_nav.common.already_up.
"""
import signal
import sys

# Ctrl-C (or the launch ending) before the node starts: end quietly.
signal.signal(signal.SIGINT, signal.SIG_DFL)  # Ctrl-C during the imports: gone, quietly

from rbx1_nav.common.already_up_ros import unless_running  # noqa: E402

if __name__ == '__main__':
    sys.exit(unless_running(sys.argv[1:], __doc__))
