#!/usr/bin/env python3
"""rostest: fake_turtlebot.py started by rosrun on a master with leftovers.

Run by fake_turtlebot_leftovers.test: /use_sim_time is true with nothing
on /clock, and /fake_turtlebot/rate is 30 from "an earlier run". The node,
started as a user would (rosrun, no _rate:= on its command line), must
warn about the missing clock after its 5 s wait (20 s of wall time allowed
for start-up on a loaded machine) and name the leftover rate.
"""
import os
import signal
import subprocess
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import RosoutWatch, wait_until  # noqa: E402

NODE = '/fake_turtlebot'


class FakeTurtlebotLeftoversTest(unittest.TestCase):

    def test_no_clock_and_a_leftover_parameter_are_named(self):
        log = RosoutWatch()
        node = subprocess.Popen(['rosrun', 'rbx1_nav', 'fake_turtlebot.py'])
        try:
            self.assertTrue(wait_until(lambda: log.find(NODE, 'from the parameter server'),
                                       wall_limit=20.0), 'no leftover warning')
            clock = log.find(NODE, 'nothing publishes /clock')
            leftover = log.find(NODE, 'from the parameter server')
        finally:
            node.send_signal(signal.SIGINT)
            node.wait(30)
        self.assertIsNotNone(clock, 'no warning about /clock')
        print('RESULT no clock: %r' % clock.msg)
        print('RESULT leftover: %r' % leftover.msg)
        self.assertIn('/use_sim_time is true but nothing publishes /clock after 5.0 s',
                      clock.msg)
        self.assertIn('rosparam set /use_sim_time false', clock.msg)
        self.assertIn('rate 30 Hz', leftover.msg)
        self.assertIn('rosparam delete /fake_turtlebot', leftover.msg)


if __name__ == '__main__':
    rospy.init_node('fake_turtlebot_leftovers_test')
    rostest.rosrun('rbx1_nav', 'fake_turtlebot_leftovers', FakeTurtlebotLeftoversTest)
