"""The ROS side of umbmark.py: drive the UMBmark squares, collect odometry's
and the true return positions, analyse them (rbx1_nav.calibration.umbmark).

The true positions come from ``~ground_truth_topic`` (rbx1_nav.calibration.
truth_ros) when set, else from the user at the terminal; without either the
node drives the runs and prints the command that analyses the measurements
afterwards. The runs go through rbx1_nav.motion.runner.runner_ros, which stops the
robot on every exit path.
"""
import os
import select
import sys

import rospy

from rbx1_nav.calibration import umbmark
from rbx1_nav.calibration.truth_ros import GroundTruth
from rbx1_nav.common.node_ros import start_node
from rbx1_nav.motion.course.precise import PRECISE_PARAMS, Breakaway, approach
from rbx1_nav.motion.runner.runner_ros import MotionRunner, guarded
from rbx1_nav.common.aborted import CourseAborted

NAME = 'umbmark'
#: Precise mode's settings, which umbmark.py declares: every run is precise
#: (Benchmark.run), so ~precise itself is not among them.
APPROACH_PARAMS = tuple(p for p in PRECISE_PARAMS if p.name != 'precise')


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
            return umbmark.parse_position(answer, side)
        except ValueError as err:
            print('  %s' % err)


class Benchmark(object):
    """Drive the runs and collect odometry's and the true return positions."""

    def __init__(self, values, choose_clock):
        self.values = values
        self.runner = MotionRunner(NAME, values, choose_clock)
        self.breakaway = Breakaway()  # precise mode's creep speeds, learned over every run
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
            label = umbmark.run_label(k, len(runs), clockwise)
            if self.interactive:
                if ask('%s: put the robot on its start mark, then press '
                       'Enter: ' % label) is None:
                    raise rospy.ROSInterruptException('shutdown at the prompt')
            elif k > 0 and v['run_pause'] > 0:
                rospy.loginfo('%s starts in %.1f s', label, v['run_pause'])
                self.runner.pause(v['run_pause'])
            truth_start = self.truth and self.truth.at(rospy.Time.now())
            course = umbmark.square_course(
                v['side'], clockwise, v['linear_speed'], v['angular_speed'],
                approach(dict(v, precise=True)), v['pause'], label, self.breakaway)
            # Unattended, the runs follow each other as one lockstep member.
            final = self.runner.run(course, stay=not self.interactive
                                    and k + 1 < len(runs))
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


def report_results(values, odometry, measured):
    """Check the positions, compute, log, write and plot; return the Result."""
    runs = values['runs']
    odometry, measured, result = umbmark.evaluate(
        odometry, measured, runs, values['side'], values['wheel_separation'])
    lines = umbmark.report(result)
    for line in lines[:-1]:
        rospy.loginfo('%s: %s', NAME, line)
    (rospy.loginfo if result.supported or umbmark.calibrated(result)
     else rospy.logwarn)('%s: %s', NAME, lines[-1])
    results_path = os.path.abspath(values['results'])
    umbmark.save(results_path, result, runs, odometry, measured)
    results, labels = [result], ['this run']
    if values['compare']:
        results = [umbmark.load(values['compare']), result]
        labels = ['before', 'after']
        rospy.loginfo('%s: %s', NAME, umbmark.compare_text(results[0], result))
    if values['plot']:
        umbmark.plot(results, values['plot'], labels)
        rospy.loginfo('%s: results in %s, plot in %s', NAME, results_path,
                      os.path.abspath(values['plot']))
    else:
        rospy.loginfo('%s: results in %s (~plot empty: no plot)', NAME, results_path)
    return result


def main(specs, choose_clock, doc):
    """main() of umbmark.py (``specs``: its parameters; ``choose_clock``: the
    runner's, MotionRunner; ``doc``: its docstring, for --help); returns the
    exit status."""
    values = start_node(NAME, specs, doc)
    if values is None:
        return 1
    if values['measurements']:  # after the fact: analyse only
        odometry = values['odometry'] or [[0.0, 0.0]] * (2 * values['runs'])
        if not values['odometry']:
            rospy.logwarn('%s: no ~odometry given: taking odometry\'s return '
                          'positions as the starts', NAME)
        try:
            report_results(values, odometry, values['measurements'])
            return 0
        except (ValueError, OSError, KeyError) as err:
            rospy.logerr('%s: %s; no correction computed', NAME, err)
            return 1
    bench = Benchmark(values, choose_clock)
    status = guarded(NAME, bench.runner, bench.run)
    if status != 0:
        return status
    if not bench.measured:
        rospy.loginfo('%s: %s', NAME, umbmark.rerun_text(
            values['runs'], values['side'], bench.odometry))
        return 0
    try:
        report_results(values, bench.odometry, bench.measured)
    except (ValueError, OSError, KeyError) as err:
        rospy.logerr('%s: %s; no correction computed', NAME, err)
        return 1
    return 0
