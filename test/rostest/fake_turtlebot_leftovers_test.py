#!/usr/bin/env python3
"""rostest: fake_turtlebot.py started as rosrun does on a master with leftovers.

Run by fake_turtlebot_leftovers.test: /use_sim_time and /lockstep are true
with nothing on /clock, and /fake_turtlebot/rate is 30 from "an earlier
run". The node, started as a user would (no _rate:= on its command line), must warn about the missing clock after its 5 s wait (20 s of wall
time allowed for start-up on a loaded machine), name the leftover rate,
then say that nothing grants lockstep steps, naming /use_sim_time, once
(its reminder comes a minute later: none in the next 12 s). It goes on
waiting: once a sim_clock starts, its odom comes at the leftover 30 Hz,
and Ctrl-C ends it with status 0. A course
started there says the clock is missing once as a warning, then gives up
with an error that says so, and exits 1.
"""
import os
import signal
import subprocess
import sys
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import CourseProcess, RosoutWatch, TopicLog, wait_until  # noqa: E402
from rosrun import rosrun  # noqa: E402

NODE = '/fake_turtlebot'
ODOM_WINDOW = 2.0  # simulated s of odom counted once a clock runs


class FakeTurtlebotLeftoversTest(unittest.TestCase):

    def test_no_clock_and_a_leftover_parameter_are_named(self):
        log = RosoutWatch()
        # The stamps (ROS s) of the robot's odom, as they arrive.
        odom = TopicLog('/odom', Odometry, lambda msg: msg.header.stamp.to_sec())
        node = subprocess.Popen(rosrun('rbx1_nav', 'fake_turtlebot.py'))
        sim_clock = None
        try:
            self.assertTrue(wait_until(lambda: log.find(NODE, 'from the parameter server'),
                                       wall_limit=20.0), 'no leftover warning')
            clock = log.find(NODE, 'nothing publishes /clock')
            leftover = log.find(NODE, 'from the parameter server')
            self.assertTrue(wait_until(lambda: log.find(NODE, 'granted a step'),
                                       wall_limit=30.0), 'no warning of no grants')
            rospy.rostime.wallsleep(12.0)
            no_grant = log.all(NODE, 'granted a step')
            # The robot goes on after its warnings: once a clock grants it
            # steps (sim_clock, as the warning says), odom comes at the
            # leftover 30 Hz, a stamp every simulated 1/30 s.
            self.assertEqual(odom.snapshot(), [], 'odom without a clock')
            sim_clock = CourseProcess(script='sim_clock.py', name='sim_clock')
            self.assertTrue(wait_until(lambda: len(odom.snapshot()) > ODOM_WINDOW * 30,
                                       wall_limit=30.0),
                            'not %.0f s of odom within 30 s (wall) of sim_clock\'s '
                            'start:\n%s' % (ODOM_WINDOW, sim_clock.output))
            stamps = odom.snapshot()
            node.send_signal(signal.SIGINT)
            status = node.wait(30)
        finally:
            if node.poll() is None:
                node.send_signal(signal.SIGINT)
                node.wait(30)
            if sim_clock is not None:
                sim_clock.interrupt()
                sim_clock.finish(30)
        window = [t for t in stamps if t <= stamps[0] + ODOM_WINDOW]
        gaps = [b - a for a, b in zip(window, window[1:])]
        print('RESULT with a clock: %d odom in the first %.1f s, from %.3f s; '
              'gaps %.4f to %.4f s; exit status %s on SIGINT'
              % (len(window), ODOM_WINDOW, stamps[0], min(gaps), max(gaps), status))
        self.assertEqual(len(window), round(ODOM_WINDOW * 30) + 1)
        for gap in gaps:
            self.assertAlmostEqual(gap, 1.0 / 30, delta=1e-6)
        self.assertEqual(status, 0, 'fake_turtlebot exited %s on SIGINT' % status)
        self.assertIsNotNone(clock, 'no warning about /clock')
        print('RESULT no clock: %r' % clock.msg)
        print('RESULT leftover: %r' % leftover.msg)
        self.assertIn('/use_sim_time is true but nothing publishes /clock after 5.0 s',
                      clock.msg)
        self.assertIn('rosparam set /use_sim_time false', clock.msg)
        self.assertIn('rate 30 Hz', leftover.msg)
        self.assertIn('rosparam delete /fake_turtlebot', leftover.msg)
        print('RESULT no grant: %r' % [m.msg for m in no_grant])
        self.assertEqual(len(no_grant), 1, [m.msg for m in no_grant])
        self.assertIn('/use_sim_time and /lockstep true', no_grant[0].msg)
        self.assertIn('rosparam set /use_sim_time false', no_grant[0].msg)

    def test_a_course_says_so_once_and_gives_up(self):
        course = CourseProcess(params={'tf_wait': 1.0})
        status = course.finish()
        out = course.output
        self.assertEqual(status, 1, out)
        lines = [line for line in course.lines if 'publishes /clock' in line]
        self.assertEqual(len(lines), 2, out)
        self.assertTrue(lines[0].startswith('[WARN]'), out)
        self.assertIn('nothing publishes /clock after 5.0 s', lines[0])
        self.assertTrue(lines[1].startswith('[ERROR]'), out)
        self.assertIn('giving up, the robot not moved: /use_sim_time is true '
                      'but nothing publishes /clock after 6.0 s', lines[1])


if __name__ == '__main__':
    rospy.init_node('fake_turtlebot_leftovers_test')
    rostest.rosrun('rbx1_nav', 'fake_turtlebot_leftovers', FakeTurtlebotLeftoversTest)
