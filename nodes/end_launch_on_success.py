#!/usr/bin/env python3
"""end_launch_on_success: run a node; when it exits with status 0, end the
roslaunch that started it the way Ctrl-C does.

Without it, roslaunch ends a launch whose required node has finished with
a red "REQUIRED process [...] has died! ... Initiating shutdown!" block,
even after a successful course. As a node's launch-prefix:

  <node ... required="true" launch-prefix="$(find rbx1_nav)/end_launch_on_success.py">

($(find) followed by a script's name gives the built script, in a devel or
an install space, without rosrun's search of the workspace at each launch.)

A node that fails (non-zero status) still ends a launch with the red block
naming its exit code. Under rostest, or with other wrapped nodes of the
launch still running (a fleet's courses), the wrapper exits with the
node's status and leaves the launch alone.

Under roslaunch, once the node has ended it also removes the node's
private parameters from the master (a later rosrun of it starts fresh),
after a node that published the launch's clock (rosbag play --clock) the
launch's /use_sim_time and /lockstep, unless another clock runs, and, in a
launch started by launch_status.py, records the node's status for it.
See rbx1_nav.common.launch_end.
"""
import signal
import sys

signal.signal(signal.SIGINT, signal.SIG_DFL)  # a signal during the imports: gone, quietly

from rbx1_nav.common.launch_end import run  # noqa: E402
from rbx1_nav.common.launch_end_ros import end_sim_time, forget_params  # noqa: E402

if __name__ == '__main__':
    sys.exit(run(sys.argv[1:], __doc__, forget=forget_params, end_clock=end_sim_time))
