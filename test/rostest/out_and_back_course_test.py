#!/usr/bin/env python3
"""Courses on the fake robot, one after another, each judged on its true
end pose.

Used by courses.test (the course nodes on the ideal robot) and
turtlebot2_remap.test. (The odometry course in the book's mode on the
ideal robot is checked against the pure model by lockstep_course_test.py,
in lockstep_1x.test and lockstep_max_stalled.test, the latter on base_link.)

~courses is a list, one test case per entry, run in its order, each from
where the previous one left the robot (a course that fails leaves the
robot wherever it stopped: the next ones still measure from there). An
entry has ``name`` (its case's), ``position_tolerance`` (m) and
``heading_tolerance`` (deg), and may give ``node``, the course node
(odom_out_and_back.py by default; every one of these courses ends where
it began), ``course_params`` (dict), its private parameters,
``remaps`` (dict), its topic remaps, ``expect_in_output``, strings that
must appear in its log, ``expect_not_in_output``, strings that must not,
and ``expect_status``. A case passes if the node
exits 0 and the simulator's ground_truth ends within the tolerances of
where that course started, with the robot stopped; with
``expect_status`` not 0, if the node exits with it and the robot never
moved. Without ~courses, one course from the private parameters of those
names. ~driver_cmd_vel (default cmd_vel) is the topic the robot's driver
takes its commands on, where the test hears them.
"""
import os
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import (CourseProcess, RobotWatch,  # noqa: E402
                            check_completed_course)

KEYS = ('node', 'course_params', 'remaps', 'position_tolerance',
        'heading_tolerance', 'expect_in_output', 'expect_not_in_output', 'expect_status')


def courses():
    """~courses, or one course from the private parameters."""
    if rospy.has_param('~courses'):
        return rospy.get_param('~courses')
    return [dict({'name': 'course'},
                 **{key: rospy.get_param('~' + key) for key in KEYS
                    if rospy.has_param('~' + key)})]


class CourseTest(unittest.TestCase):
    watch = None

    @classmethod
    def setUpClass(cls):
        cls.watch = RobotWatch(cmd_vel=rospy.get_param('~driver_cmd_vel', 'cmd_vel'))

    def run_course(self, entry):
        start = self.watch.wait_for_truth()
        course = CourseProcess(params=entry.get('course_params', {}),
                               script=entry.get('node', 'odom_out_and_back.py'),
                               remaps=entry.get('remaps'))
        try:
            if entry.get('expect_status', 0):
                self.check_refused(course, start, entry['expect_status'])
            else:
                check_completed_course(self, self.watch, course, start, tolerances=(
                    entry['position_tolerance'], entry['heading_tolerance']))
        finally:
            course.cleanup()
        for text in entry.get('expect_in_output', []):
            self.assertIn(text, course.output)
        for text in entry.get('expect_not_in_output', []):
            self.assertNotIn(text, course.output)


    def check_refused(self, course, start, status):
        """The course exited with ``status`` and the robot never moved."""
        self.assertEqual(course.wait(), status, course.output)
        self.assertNotIn('Course complete', course.output)
        self.assertEqual(self.watch.motion_commands(), [], course.output)
        self.assertEqual(self.watch.moved_since(start), 0.0, course.output)


def add_cases(entries):
    """A test method per entry, numbered so that unittest keeps their order."""
    for k, entry in enumerate(entries, 1):
        setattr(CourseTest, 'test_%02d_%s' % (k, entry['name']),
                lambda self, entry=entry: self.run_course(entry))


if __name__ == '__main__':
    rospy.init_node('out_and_back_course_test')
    add_cases(courses())
    rostest.rosrun('rbx1_nav', 'out_and_back_course', CourseTest)
