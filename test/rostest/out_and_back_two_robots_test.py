#!/usr/bin/env python3
"""Two robots in two namespaces on one master run the course together.

Run by out_and_back_two_robots.test: robot1 and robot2 each have a fake
robot publishing robotN/odom -> robotN/base_footprint, sharing one clock.
Each course node runs in its robot's namespace (relative cmd_vel) with its
frames set by parameter; both must finish within tolerance, in precise
mode (~precise) with legs of ~goal_distance (m) from the .test: any
cross-talk between the robots would show up as errors of metres.
"""
import os
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import (CourseProcess, RobotWatch,  # noqa: E402
                            check_completed_course)

ROBOTS = ('robot1', 'robot2')


class TwoRobotsTest(unittest.TestCase):

    def test_both_robots_complete_the_course(self):
        watches = dict((ns, RobotWatch(ns)) for ns in ROBOTS)
        starts = dict((ns, w.wait_for_truth()) for ns, w in watches.items())
        precise = bool(rospy.get_param('~precise', False))
        courses = dict((ns, CourseProcess(ns=ns, params={
            'precise': str(precise).lower(),
            'tf_timeout': float(rospy.get_param('~tf_timeout', 1.0)),
            'goal_distance': float(rospy.get_param('~goal_distance', 1.0)),
            'odom_frame': ns + '/odom',
            'base_frame': '/%s/base_footprint' % ns}))  # slash gets stripped
            for ns in ROBOTS)
        try:
            for ns in ROBOTS:
                check_completed_course(self, watches[ns], courses[ns],
                                       starts[ns])
                self.assertIn('Following tf %s/odom -> %s/base_footprint'
                              % (ns, ns), courses[ns].output)
                # In a fleet, progress and summary lines name their robot.
                self.assertIn('%s: leg 1/' % ns, courses[ns].output)
                self.assertIn('%s: Course complete' % ns, courses[ns].output)
        finally:
            for course in courses.values():
                course.cleanup()


if __name__ == '__main__':
    rospy.init_node('out_and_back_two_robots_test')
    rostest.rosrun('rbx1_nav', 'out_and_back_two_robots', TwoRobotsTest)
