#!/usr/bin/env python3
"""launch_status: roslaunch a course and exit with the course's status.

roslaunch exits 0 even when a required course fails (it prints the red
"REQUIRED process [...] has died!" block and shuts down), so a script
cannot tell success from failure by roslaunch's status. This runs
roslaunch with the same arguments and then exits with the status of the
first course (a node run through end_launch_on_success.py: every course
of this package's launch files) that failed, else with roslaunch's own,
and prints one line saying which:

  rosrun rbx1_nav launch_status.py rbx1_nav nav_square.launch sim:=true
  echo $?    # 0 after "Course complete", the course's status (1) otherwise

Ctrl-C goes to roslaunch as usual (the course then exits 1). See
rbx1_nav.common.launch_end.
"""
import signal
import sys

signal.signal(signal.SIGINT, signal.SIG_DFL)  # a signal during the imports: gone, quietly

from rbx1_nav.common.launch_end import run_launch  # noqa: E402

if __name__ == '__main__':
    sys.exit(run_launch(sys.argv[1:], __doc__))
