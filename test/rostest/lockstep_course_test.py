#!/usr/bin/env python3
"""Under lockstep, the ROS graph drives exactly the pure model's course.

The course node (odom_out_and_back.py with ~course_params) runs against the
fake robot under lockstep simulated time. With ~stalls true, the test
freezes the graph's processes (the robot, sim_clock, the course) one at a
time at random, as a loaded machine takes a process off the CPU, but
often and for long (1 to 30 ms out of every 2 to 20): any message that
could arrive late does. That load must have been there: the freezing
thread must not have failed, and must have frozen each of the three at
least once and ~min_stalls times in all. The reference is the same
course run in plain Python on the simulator's own model
(test/helpers/course_model.py: the ideal robot, each command held for
one control period): what the graph does when no message is late. The
true end pose must match it within ~match_position (m) and
~match_heading (deg), whatever the clock's speed (the .test files run it
at 1x and at max with stalls) and the load, and end within
~position_tolerance (m) and ~heading_tolerance (deg) of the start, the
robot stopped; each of ~expect_in_output (strings) must be in the
course's log. What stalls leave out (lockstep_max_stalled.test says
what) is the bench's: the same files beside real CPU burners, their
figures against the idle ones (make bench's determinism section,
bench/suite/determinism.py), and bench/accuracy/soak.py. Burners in the
suite would cost as much CPU as the graph they slow.
"""
import math
import os
import random
import signal
import sys
import threading
import time
import traceback
import unittest

import rosgraph
import rospy
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import (CourseProcess, RobotWatch,  # noqa: E402
                            check_completed_course)

from course_model import reference_end_pose  # noqa: E402
from master import node_pid  # noqa: E402
from rbx1_nav.transform_utils import normalize_angle  # noqa: E402

#: Seed of the stalls: which process, when and how long. The end pose must
#: not depend on it (it is the load's stand-in), so any seed would do.
STALL_SEED = 1


class Stalls(object):
    """Freezes one of ``pids`` at a time (SIGSTOP, then SIGCONT) at random
    until :meth:`stop`: 1 to 30 wall ms every 2 to 20 ms; counts them by
    process. Whatever ends the thread early is kept in ``error``: a thread
    that died would leave an unloaded run passing as a loaded one."""

    def __init__(self, pids, seed=STALL_SEED):
        self.pids = pids
        self.counts = dict.fromkeys(pids, 0)
        self.error = None
        self._random = random.Random(seed)
        self._done = threading.Event()
        self._started = time.monotonic()
        self.seconds = None  # wall s the thread ran, at stop()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self):
        try:
            while not self._done.wait(self._random.uniform(0.002, 0.020)):
                self._freeze(self._random.choice(self.pids))
        except BaseException:  # kept for the test to fail on
            self.error = traceback.format_exc()

    def _freeze(self, pid):
        try:
            os.kill(pid, signal.SIGSTOP)
            time.sleep(self._random.uniform(0.001, 0.030))
        except ProcessLookupError:  # the course has just ended
            return
        finally:
            try:
                os.kill(pid, signal.SIGCONT)
            except ProcessLookupError:
                pass
        self.counts[pid] += 1

    def stop(self):
        """Ends the stalls, every process running; returns their count."""
        self._done.set()
        self._thread.join()
        self.seconds = time.monotonic() - self._started
        return sum(self.counts.values())


class LockstepCourseTest(unittest.TestCase):

    def test_graph_matches_the_model_under_load(self):
        params = rospy.get_param('~course_params', {})
        expected = reference_end_pose(params)
        watch = RobotWatch()
        start = watch.wait_for_truth()
        course = CourseProcess(params=params)
        stalls, frozen = None, {}
        if rospy.get_param('~stalls', False):
            master = rosgraph.Master(rospy.get_name())
            frozen = {'the robot': node_pid(master, '/fake_turtlebot'),
                      'sim_clock': node_pid(master, '/sim_clock'),
                      'the course': course.proc.pid}
            stalls = Stalls(list(frozen.values()))
        try:
            check_completed_course(self, watch, course, start)
            for text in rospy.get_param('~expect_in_output', []):
                self.assertIn(text, course.output)
        finally:
            if stalls:
                # Their number follows the wall clock: a figure no run repeats.
                print('RESULT %d stalls in wall time (%.1f s wall); %s'
                      % (stalls.stop(), stalls.seconds, ', '.join(
                          '%s %d wall' % (name, stalls.counts[pid])
                          for name, pid in frozen.items())))
            course.cleanup()
        if stalls:
            self.check_stalls(stalls, frozen)
        final = watch.pose()
        dx, dy = final.x - expected.x, final.y - expected.y
        dyaw = math.degrees(normalize_angle(final.yaw - expected.yaw))
        print('RESULT lockstep end pose (%.6f, %.6f, %.4f deg), model (%.6f, '
              '%.6f, %.4f deg): off by %.4f mm, %.5f deg'
              % (final.x, final.y, math.degrees(final.yaw), expected.x,
                 expected.y, math.degrees(expected.yaw),
                 1000 * math.hypot(dx, dy), dyaw))
        self.assertLess(math.hypot(dx, dy),
                        float(rospy.get_param('~match_position')))
        self.assertLess(abs(dyaw), float(rospy.get_param('~match_heading')))

    def check_stalls(self, stalls, frozen):
        """The load was there: the freezing thread ran to the end, froze
        at least ~min_stalls times, and froze each process of ``frozen``
        ({name: pid}) at least once."""
        self.assertIsNone(stalls.error, 'the thread freezing processes failed:\n%s'
                          % stalls.error)
        least = int(rospy.get_param('~min_stalls'))
        self.assertGreaterEqual(sum(stalls.counts.values()), least,
                                'fewer stalls than ~min_stalls: %s' % stalls.counts)
        for name, pid in frozen.items():
            self.assertGreater(stalls.counts[pid], 0, '%s (pid %d) was never frozen: %s'
                               % (name, pid, stalls.counts))


if __name__ == '__main__':
    rospy.init_node('lockstep_course_test')
    rostest.rosrun('rbx1_nav', 'lockstep_course', LockstepCourseTest)
