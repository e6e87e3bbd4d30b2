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
from zero, rbx1_nav.calibration.umbmark), the factors for the driver
(diff_drive_controller's three multipliers, a TurtleBot driver's
odom_angular_scale_correction); otherwise it says that E_max,syst is within
the noise and about how many runs would be needed. It writes them to
~results (YAML; corrections null when not supported) and plots them to
~plot (PNG), together with an earlier ~compare results file.

The paper's squares have 4 m sides; ~side defaults to 1 m. Exit status 0
with a result, 1 otherwise.
"""
import os
import select
import sys

import rospy
import yaml

from rbx1_nav.common import params
from rbx1_nav.calibration import umbmark
from rbx1_nav.motion.command import MAX_ANGULAR_SPEED, MAX_LINEAR_SPEED
from rbx1_nav.motion.precise import PRECISE_PARAMS, approach
from rbx1_nav.common.params import param
from rbx1_nav.common.node_ros import exit_node, start_node
from rbx1_nav.motion.runner_ros import (CourseAborted, MotionRunner, common_params,
                                 guarded)
from rbx1_nav.calibration.truth_ros import TRUTH_PARAM, GroundTruth

NAME = 'umbmark'
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
    param('measurements', [], params.pairs, 'm',
          'true return positions [[x, y], ...]: analyse only'),
    param('odometry', [], params.pairs, 'm',
          "odometry's return positions of the same runs"),
    param('results', 'umbmark.yaml', params.text, '', 'results file (YAML)'),
    param('plot', 'umbmark.png', params.text, '', 'plot file (PNG)'),
    param('compare', '', params.text, '', 'an earlier results file to plot '
          'beside these (before / after)', allow_empty=True),
) + tuple(p for p in PRECISE_PARAMS if p.name != 'precise') + common_params(
    rate=20.0)


def ask(question):
    """A line typed at the terminal, or None on shutdown (Ctrl-C)."""
    sys.stdout.write(question)
    sys.stdout.flush()
    while not rospy.is_shutdown():
        ready, _, _ = select.select([sys.stdin], [], [], 0.2)
        if ready:
            return sys.stdin.readline().strip()
    return None


def ask_position(label, side):
    """Ask for a run's true return position until a usable one comes."""
    while True:
        answer = ask('%s: where did the robot stop, relative to its start '
                     'mark? "x y" in metres (x forward, y left): ' % label)
        if answer is None:
            raise rospy.ROSInterruptException('shutdown at the prompt')
        try:
            x, y = (float(part) for part in answer.replace(',', ' ').split())
        except ValueError:
            print('  type two numbers in metres, e.g. "0.012 -0.004"')
            continue
        try:
            return tuple(umbmark.check_errors([[x, y]], 1, side, 'position')[0])
        except ValueError as err:
            print('  %s; try again' % err)


class Benchmark(object):
    """Drive the runs and collect odometry's and the true return positions."""

    def __init__(self, values):
        self.values = values
        self.runner = MotionRunner(NAME, values)
        topic = values['ground_truth_topic']
        self.truth = GroundTruth(topic) if topic else None
        self.interactive = not self.truth and sys.stdin.isatty()
        self.odometry, self.measured = [], []

    def run(self):
        v = self.values
        self.runner.start()
        if self.truth and self.truth.wait(v['tf_wait']) is None:
            raise CourseAborted('nothing on %s after %.1f s: is the simulator '
                                'running?' % (self.truth.topic, v['tf_wait']))
        runs = [True] * v['runs'] + [False] * v['runs']
        for k, clockwise in enumerate(runs):
            label = 'run %d/%d (%s)' % (k + 1, len(runs),
                                        'cw' if clockwise else 'ccw')
            if self.interactive:
                if ask('%s: put the robot on its start mark, then press '
                       'Enter: ' % label) is None:
                    raise rospy.ROSInterruptException('shutdown at the prompt')
            elif k > 0 and v['run_pause'] > 0:
                rospy.loginfo('%s starts in %.1f s', label, v['run_pause'])
                rospy.sleep(v['run_pause'])
            truth_start = self.truth and self.truth.at(rospy.Time.now())
            course = umbmark.square_course(
                v['side'], clockwise, v['linear_speed'], v['angular_speed'],
                approach(dict(v, precise=True)), v['pause'], label)
            final = self.runner.run(course)
            odom = umbmark.relative(course.start_pose, final)
            self.odometry.append(odom)
            rospy.loginfo('%s: odometry says it stopped at (%+.1f, %+.1f) mm '
                          'from its start', label, 1000 * odom[0], 1000 * odom[1])
            if self.truth:
                true = umbmark.relative(truth_start,
                                        self.truth.at(self.runner.last_tick))
                rospy.loginfo('%s: ground truth: (%+.1f, %+.1f) mm', label,
                              1000 * true[0], 1000 * true[1])
                self.measured.append(true)
            elif self.interactive:
                self.measured.append(ask_position(label, v['side']))


def analyse(values, odometry, measured):
    """Check the positions, compute, print, write and plot; return the Result."""
    count = 2 * values['runs']
    measured = umbmark.check_errors(measured, count, values['side'],
                                    '~measurements')
    odometry = umbmark.check_errors(odometry, count, values['side'], '~odometry')
    runs = values['runs']
    result = umbmark.analyse_runs(odometry, measured, runs, values['side'],
                                  values['wheel_separation'])
    lines = umbmark.report(result)
    for line in lines[:-1]:
        rospy.loginfo('%s: %s', NAME, line)
    (rospy.loginfo if result.supported else rospy.logwarn)('%s: %s', NAME,
                                                           lines[-1])
    results_path = os.path.abspath(values['results'])
    with open(results_path, 'w') as f:
        yaml.safe_dump({
            'side': values['side'], 'runs': runs,
            'wheel_separation': values['wheel_separation'],
            'odometry': odometry.tolist(), 'measurements': measured.tolist(),
            'e_max_syst': result.e_max, 'ed': result.ed, 'eb': result.eb,
            'scatter': {label: {'sd': spread.sd, 'se': spread.se} for label, spread
                        in (('cw', result.scatter_cw), ('ccw', result.scatter_ccw))},
            'supported': result.supported,
            'corrections': (umbmark.corrections(result) if result.supported
                            else None)}, f)
    results, labels = [result], ['this run']
    if values['compare']:
        results, labels = [load(values['compare']), result], ['before', 'after']
        rospy.loginfo('%s: E_max,syst before %.1f mm, after %.1f mm (%.1fx)',
                      NAME, 1000 * results[0].e_max, 1000 * result.e_max,
                      results[0].e_max / max(result.e_max, 1e-12))
    umbmark.plot(results, values['plot'], labels)
    rospy.loginfo('%s: results in %s, plot in %s', NAME, results_path,
                  os.path.abspath(values['plot']))
    return result


def load(path):
    """A Result from a results file this node wrote."""
    with open(path) as f:
        saved = yaml.safe_load(f)
    return umbmark.analyse_runs(saved['odometry'], saved['measurements'],
                                saved['runs'], saved['side'],
                                saved['wheel_separation'])


def main():
    values = start_node(NAME, PARAMS, __doc__)
    if values is None:
        return 1
    if values['measurements']:  # after the fact: analyse only
        odometry = values['odometry'] or [[0.0, 0.0]] * (2 * values['runs'])
        if not values['odometry']:
            rospy.logwarn('%s: no ~odometry given: taking odometry\'s return '
                          'positions as the starts', NAME)
        try:
            analyse(values, odometry, values['measurements'])
            return 0
        except (ValueError, OSError, KeyError) as err:
            rospy.logerr('%s: %s; no correction computed', NAME, err)
            return 1
    bench = Benchmark(values)
    status = guarded(NAME, bench.runner, bench.run)
    if status != 0:
        return status
    if not bench.measured:
        rospy.loginfo(
            '%s: all runs done. Measure where each run stopped (x forward, y '
            'left of its start, metres; clockwise runs first), then run:\n'
            "  rosrun rbx1_nav umbmark.py _runs:=%d _side:=%g _odometry:='%s' "
            "_measurements:='[[x1, y1], ...]'", NAME, values['runs'],
            values['side'], [[round(x, 4), round(y, 4)] for x, y in
                             bench.odometry])
        return 0
    try:
        analyse(values, bench.odometry, bench.measured)
    except (ValueError, OSError, KeyError) as err:
        rospy.logerr('%s: %s; no correction computed', NAME, err)
        return 1
    return 0


if __name__ == '__main__':
    exit_node(NAME, main())
