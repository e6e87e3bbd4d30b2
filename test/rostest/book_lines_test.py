#!/usr/bin/env python3
"""rostest: the book's five lines, typed as the book types them, work.

ROS By Example's odometry chapter (7.8) has its reader type, for the
simulator and then for a TurtleBot's fused odometry:

  roslaunch rbx1_bringup fake_turtlebot.launch
  rosrun rviz rviz -d `rospack find rbx1_nav`/sim.rviz
  rosrun rbx1_nav odom_out_and_back.py
  roslaunch rbx1_bringup odom_ekf.launch
  rosrun rviz rviz -d `rospack find rbx1_nav`/nav_ekf.rviz

and then the course again ("just like we did in simulation"). The test
types each line through bash (backquotes and all) on this rostest's master,
in that order, RViz on a virtual screen (Xvfb), and checks each result:
- the robot is up (its ground truth arrives);
- RViz shows sim.rviz: the file the line names says fixed frame odom,
  RViz runs with it, and its screenshot after the course shows the red
  odometry and blue ground-truth arrows (nothing is drawn with a fixed
  frame tf does not know, nor with RViz's default view), and RViz logged
  no error: the suite's one check that each view draws its arrows
  (test/integration/test_rviz_views.py checks where sim.rviz draws them,
  on the realistic robot);
- the course completes: exit 0, "Course complete", and the true end pose
  within ~position_tolerance (m) and ~heading_tolerance (deg) of its start,
  the robot stopped (check_completed_course); under lockstep the course is
  deterministic: its true end matches the pure model's
  (test/helpers/course_model.py, the first course from the origin, the
  second from where the first ended) within ~match_position (m) and
  ~match_heading (deg);
- odom_ekf follows the book's /odom_combined and /odom_ekf flows
  (~ekf_messages within ~ekf_wait simulated s, in odom, at the true pose);
- RViz shows nav_ekf.rviz (fixed frame odom) and, after the course again
  (completing as above), its green EKF and blue ground-truth arrows.
~first_line_args go after the first line (sim_speed:=max: lockstep at
full speed). Not deterministic, as neither keeps simulated time: what RViz
has drawn when the screenshot is taken (its pixel counts), and how many
/odom_ekf messages the test's wall-clock poll has counted. The first RViz
is closed before the second starts (CPU).
Screenshots go to the workspace's test_artifacts/.
"""
import math
import os
import subprocess
import sys
import time
import unittest

import rosgraph
import rospkg
import rospy
import rostest
import yaml
from nav_msgs.msg import Odometry

from rbx1_nav.transform_utils import normalize_angle

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, '..', 'helpers'))
from course_harness import (RobotWatch, check_completed_course,  # noqa: E402
                            wait_until)
from course_model import reference_end_poses  # noqa: E402
from rviz_screen import (BLUE, GREEN, MIN_PIXELS, RED, RVIZ_ENV,  # noqa: E402
                         Processes, colour_counts, rviz_errors, wait_for_picture)

BOOK = [
    'roslaunch rbx1_bringup fake_turtlebot.launch',
    'rosrun rviz rviz -d `rospack find rbx1_nav`/sim.rviz',
    'rosrun rbx1_nav odom_out_and_back.py',
    'roslaunch rbx1_bringup odom_ekf.launch',
    'rosrun rviz rviz -d `rospack find rbx1_nav`/nav_ekf.rviz',
]
WALL_LIMIT = 120.0  # s for any one step; a guard, not a measure


def artifacts():
    for prefix in os.environ.get('CMAKE_PREFIX_PATH', '').split(':'):
        if prefix.endswith('/devel'):
            path = os.path.join(os.path.dirname(prefix), 'test_artifacts')
            os.makedirs(path, exist_ok=True)
            return path
    return rospkg.get_log_dir()


class TypedCourse(object):
    """A typed course line, as check_completed_course wants it."""

    def __init__(self, procs, name, proc):
        self.procs, self.name, self.proc = procs, name, proc

    def wait(self, wall_limit=WALL_LIMIT):
        try:
            return self.proc.wait(wall_limit)
        except subprocess.TimeoutExpired:
            self.procs.stop_one(self.proc)
            raise AssertionError('the course still ran after %.0f s wall:\n%s'
                                 % (wall_limit, self.output))

    @property
    def output(self):
        return self.procs.log(self.name)


class BookLinesTest(unittest.TestCase):

    def setUp(self):
        self.master = rosgraph.Master(rospy.get_name())
        # The typed lines' output beside this run's other logs.
        self.procs = Processes(dict(os.environ, **RVIZ_ENV), os.path.join(
            rospkg.get_log_dir(), rospy.get_param('/run_id', '')))
        self.count = 0

    def tearDown(self):
        self.procs.stop()

    def type(self, line, name):
        """Type ``line`` in a new terminal (bash, in the background)."""
        self.count += 1
        log = 'book_line_%d_%s' % (self.count, name)
        print('TYPED %s' % line)
        return log, self.procs.start(log, ['bash', '-c', line])

    def rviz_up(self, log, proc, config, topic):
        """Wait until the RViz the line started runs with ``config`` (as
        ``rospack find rbx1_nav`` finds it, fixed frame odom) and draws
        ``topic``."""
        path = os.path.join(rospkg.RosPack().get_path('rbx1_nav'), config)
        with open(path) as f:
            view = yaml.safe_load(f)
        self.assertEqual(view['Visualization Manager']['Global Options']
                         ['Fixed Frame'], 'odom', path)

        def subscribed():
            _, subscribers, _ = self.master.getSystemState()
            return any(t == topic and any(n.startswith('/rviz') for n in nodes)
                       for t, nodes in subscribers)
        self.assertTrue(wait_until(lambda: subscribed() or proc.poll() is not None,
                                   WALL_LIMIT) and proc.poll() is None,
                        'RViz never subscribed %s:\n%s' % (topic, self.procs.log(log)))
        with open('/proc/%d/cmdline' % proc.pid, 'rb') as f:
            argv = f.read().decode().split('\0')
        self.assertIn(path, argv, 'RViz runs with %s' % argv)

    def screenshot(self, log, proc, name, colours):
        """Grab the screen until each colour's arrows are drawn, MIN_PIXELS
        of each in the 3D view (RViz draws on the wall clock, slowly on a
        loaded machine: up to rviz_screen.PICTURE_LIMIT s, failing at once
        if RViz exits); assert RViz logged no error."""
        shot, took = wait_for_picture(
            self.procs.env['DISPLAY'], proc, lambda: self.procs.log(log),
            lambda shot: min(colour_counts(shot, colours).values()) >= MIN_PIXELS,
            what=lambda shot: 'pixels %s' % colour_counts(shot, colours))
        counts = colour_counts(shot, colours)
        path = os.path.join(artifacts(), 'book_lines_%s.png' % name)
        shot.save(path)
        # RViz is no lockstep member: what it has drawn follows the wall clock.
        print('RESULT %s: %s, drawn after %.1f s wall; screenshot %s' % (name, ', '.join(
            '%s %d pixels (wall-timed)' % item for item in counts.items()), took, path))
        self.assertEqual(rviz_errors(self.procs.log(log)), [])

    def course(self, watch, model):
        """The typed course completes near its start and ends where the
        pure model's course does (``model``, its true end pose)."""
        start = watch.pose()
        log, proc = self.type(BOOK[2], 'course')
        began = time.monotonic()
        check_completed_course(self, watch, TypedCourse(self.procs, log, proc),
                               start)
        print('RESULT course: %.1f s wall' % (time.monotonic() - began))
        end = watch.pose()
        off = math.hypot(end.x - model.x, end.y - model.y)
        turn = math.degrees(normalize_angle(end.yaw - model.yaw))
        print('RESULT course end (%.6f, %.6f, %.4f deg), model (%.6f, %.6f, '
              '%.4f deg): off by %.4f mm, %.5f deg'
              % (end.x, end.y, math.degrees(end.yaw), model.x, model.y,
                 math.degrees(model.yaw), 1000 * off, turn))
        self.assertLess(off, float(rospy.get_param('~match_position')))
        self.assertLess(abs(turn), float(rospy.get_param('~match_heading')))

    def test_the_books_lines_work_as_typed(self):
        # Fails without Xvfb or PIL.ImageGrab: a skip would show as a pass,
        # and RViz's view is half of what this checks.
        self.procs.start_xvfb()
        # The book's course twice, one after the other: where it ends.
        models = reference_end_poses({}, courses=2)

        # 1. The robot.
        self.type(BOOK[0] + ' ' + rospy.get_param('~first_line_args', ''),
                  'robot')
        watch = RobotWatch()
        watch.wait_for_truth(wall_limit=60.0)

        # 2. RViz with sim.rviz; 3. the course; the red and blue arrows.
        log, rviz = self.type(BOOK[1], 'rviz_sim')
        self.rviz_up(log, rviz, 'sim.rviz', '/odom')
        self.course(watch, models[0])
        self.screenshot(log, rviz, 'sim', {'odometry (red)': RED,
                                           'ground truth (blue)': BLUE})
        began = time.monotonic()
        self.procs.stop_one(rviz)
        print('RESULT RViz closed in %.1f s wall' % (time.monotonic() - began))

        # 4. odom_ekf: follows the book's /odom_combined, /odom_ekf flows.
        log, _ = self.type(BOOK[3], 'odom_ekf')
        received = []
        sub = rospy.Subscriber('/odom_ekf', Odometry, received.append)
        wanted = int(rospy.get_param('~ekf_messages'))
        wait = rospy.Duration(float(rospy.get_param('~ekf_wait')))
        self.assertTrue(wait_until(lambda: len(received) > 0, WALL_LIMIT),
                        'nothing on /odom_ekf:\n' + self.procs.log(log))
        first = received[0].header.stamp
        self.assertTrue(wait_until(lambda: len(received) >= wanted
                                   or received[-1].header.stamp - first > wait,
                                   WALL_LIMIT))
        sub.unregister()
        got = list(received)
        # Counted until the test's wall-clock poll saw enough.
        print('RESULT /odom_ekf: %d messages (wall-timed) in %.2f simulated s (wall-timed)' % (
            len(got), (got[-1].header.stamp - first).to_sec()))
        self.assertGreaterEqual(len(got), wanted, 'too few on /odom_ekf')
        truth = watch.pose()
        tolerance = float(rospy.get_param('~position_tolerance'))
        for msg in got:
            self.assertEqual((msg.header.frame_id, msg.child_frame_id),
                             ('odom', 'base_footprint'))
            p = msg.pose.pose.position
            self.assertLess(abs(complex(p.x - truth.x, p.y - truth.y)),
                            tolerance, 'odom_ekf away from the true pose')
        self.assertLess(got[0].header.stamp, got[-1].header.stamp)
        self.assertIn('following /odom_combined', self.procs.log(log))

        # 5. RViz with nav_ekf.rviz; the course again, as the book has it.
        log, rviz = self.type(BOOK[4], 'rviz_ekf')
        self.rviz_up(log, rviz, 'nav_ekf.rviz', '/odom_ekf')
        self.course(watch, models[1])
        self.screenshot(log, rviz, 'nav_ekf', {'EKF odometry (green)': GREEN,
                                               'ground truth (blue)': BLUE})


if __name__ == '__main__':
    rospy.init_node('book_lines_test')
    rostest.rosrun('rbx1_nav', 'book_lines', BookLinesTest)
