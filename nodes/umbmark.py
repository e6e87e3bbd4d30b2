#!/usr/bin/env python3
"""umbmark.py - UMBmark: find unequal wheel diameters and the true wheel base.

Borenstein and Feng's bidirectional square test (rbx1_nav.calibration.umbmark): ~runs
squares of ~side clockwise, then as many counter-clockwise, each in precise
mode on odometry (tf odom -> base). After each run the true return position
relative to the run's start is needed:

* simulation: ~ground_truth_topic (e.g. ground_truth) measures it;
* a real robot, at a terminal: the node asks for it after each run
  ("x y" in metres, x forward and y left of the start mark) and waits for
  Enter before each run, so the robot can be put back on its mark;
* without a terminal: the node drives every run, pausing ~run_pause s
  between them for the user to mark where the robot stopped, and prints the
  command that analyses the measurements afterwards: ~measurements (the
  2 x ~runs true return positions, clockwise runs first) with ~odometry
  (odometry's, as printed); given ~measurements, the node drives nothing.

It prints the return errors, each direction's scatter (standard deviation,
standard error of the centre of gravity), E_max,syst, Ed, Eb and, when the
data support a correction (a centre of gravity more than 2 standard errors
and 2 mm from zero, rbx1_nav.calibration.umbmark), the factors for the
driver (diff_drive_controller's three multipliers, a TurtleBot driver's
odom_angular_scale_correction); otherwise it says that the robot is
calibrated as far as the runs tell, and about how many runs would show an
error of that size (one run each way tells neither). It writes them to
~results (YAML; corrections null when not supported) and plots them to
~plot (PNG; empty: no plot), together with an earlier ~compare results file.

Publishes:  cmd_vel (geometry_msgs/Twist), relative.
Subscribes: odom (its velocity, as every motion node) and, when set,
            ~ground_truth_topic (nav_msgs/Odometry).

The paper's squares have 4 m sides; ~side defaults to 1 m. Exit status 0
with a result, 1 otherwise.
"""
import signal

signal.signal(signal.SIGINT, signal.SIG_DFL)  # a signal during the imports: gone, quietly

from rbx1_nav.calibration.truth_ros import TRUTH_PARAM  # noqa: E402
from rbx1_nav.calibration.umbmark_ros import APPROACH_PARAMS, NAME, main  # noqa: E402
from rbx1_nav.common import params, params_lists  # noqa: E402
from rbx1_nav.common.node_ros import exit_node  # noqa: E402
from rbx1_nav.entry.course_clock_ros import course_clock  # noqa: E402
from rbx1_nav.common.params import param  # noqa: E402
from rbx1_nav.motion.course.command import MAX_ANGULAR_SPEED, MAX_LINEAR_SPEED  # noqa: E402
from rbx1_nav.motion.runner.runner_params import common_params  # noqa: E402

PARAMS = (
    param('runs', 5, params.integer, '', 'squares in each direction',
          minimum=1, maximum=50),
    param('side', 1.0, params.number, 'm', 'side of the square',
          minimum=0.1, maximum=20.0),
    param('linear_speed', 0.2, params.number, 'm/s', 'forward speed',
          maximum=MAX_LINEAR_SPEED, **params.POSITIVE),
    param('angular_speed', 0.5, params.number, 'rad/s', 'turn rate',
          maximum=MAX_ANGULAR_SPEED, **params.POSITIVE),
    param('pause', 1.0, params.number, 's', 'stop after each side and turn',
          minimum=0.0, maximum=60.0),
    param('run_pause', 5.0, params.number, 's',
          'stop between runs (no terminal)', minimum=0.0, maximum=600.0),
    param('wheel_separation', 0.26, params.number, 'm',
          'the wheel base the driver assumes', minimum=0.01, maximum=10.0),
    TRUTH_PARAM,
    param('measurements', [], params_lists.pairs, 'm',
          'true return positions [[x, y], ...]: analyse only'),
    param('odometry', [], params_lists.pairs, 'm',
          "odometry's return positions of the same runs"),
    param('results', 'umbmark.yaml', params.text, '', 'results file (YAML)'),
    param('plot', 'umbmark.png', params.text, '', 'plot file (PNG); empty for none',
          allow_empty=True),
    param('compare', '', params.text, '', 'an earlier results file to plot '
          'beside these (before / after)', allow_empty=True),
) + APPROACH_PARAMS + common_params(
    rate=20.0)


if __name__ == '__main__':
    exit_node(NAME, main(PARAMS, course_clock, __doc__))
