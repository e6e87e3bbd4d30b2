#!/usr/bin/env python3
"""teleop_keyboard.py - drive the robot from the keyboard of a terminal.

Keys as in teleop_twist_keyboard (rbx1_nav.motion.teleop.teleop has the map, the speed
steps and the key-release timeout): hold i to drive forward, j/l to turn,
u/o/m/. for arcs, k or space to stop; q/z w/x e/c change the speeds; Q or
Ctrl-C stops the robot and quits.

Publishes:  cmd_vel (geometry_msgs/Twist), relative, so remap or namespace it.

The start speeds ~linear_speed and ~angular_speed must not exceed
~max_linear_speed and ~max_angular_speed.
Needs a terminal on stdin: run it with rosrun, or from a launch file with
launch-prefix="xterm -e". Exit status: 0 after a quit (key, Ctrl-C, SIGINT,
SIGTERM, rosnode kill, terminal closed), 1 on bad parameters, no terminal or
an error. The robot is always sent a stop and the terminal is restored.
"""
import signal

signal.signal(signal.SIGINT, signal.SIG_DFL)  # a signal during the imports: gone, quietly

from rbx1_nav.common.node_ros import exit_node  # noqa: E402
from rbx1_nav.motion.teleop.teleop import PARAMS  # noqa: E402
from rbx1_nav.motion.teleop.teleop_ros import main  # noqa: E402

NAME = 'teleop_keyboard'

if __name__ == '__main__':
    exit_node(NAME, main(PARAMS, __doc__))
