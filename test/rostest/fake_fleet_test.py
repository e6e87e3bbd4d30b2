#!/usr/bin/env python3
"""A fleet in one fake_fleet.py process: every robot completes its course.

Run by fake_fleet.test: fleet.launch starts fake_fleet.py with robot1 ..
robot3. One odom_out_and_back.py runs in each robot's namespace with the
robot's frames and its tf remapped to the robot's own topic (/tf:=tf
/tf_static:=tf_static, as fleet.launch's course:=true does). Each course
must exit 0 and leave its robot stopped within ~position_tolerance (m) and
~heading_tolerance (deg) of where it started, measured on the robot's
ground_truth. Each robot's tf and tf_static carry that robot's frames only
and nothing publishes /tf: the courses followed their own robot's topic.
"""
import os
import sys
import threading
import unittest

import rospy
import rostest
from tf2_msgs.msg import TFMessage

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import (CourseProcess, RobotWatch, RosoutWatch,  # noqa: E402
                            check_completed_course)

OWN_TF = {'/tf': 'tf', '/tf_static': 'tf_static'}


class TfWatch(object):
    """The (parent, child) frame pairs seen on a tf topic, and how many messages."""

    def __init__(self, topic):
        self.lock = threading.Lock()
        self.pairs = set()
        self.count = 0
        rospy.Subscriber(topic, TFMessage, self._on_tf)

    def _on_tf(self, msg):
        with self.lock:
            self.count += 1
            self.pairs.update((t.header.frame_id, t.child_frame_id)
                              for t in msg.transforms)


class FakeFleetTest(unittest.TestCase):

    def test_every_robot_completes_its_course_on_its_own_tf(self):
        robots = rospy.get_param('~robots')
        rosout = RosoutWatch()
        shared = TfWatch('/tf'), TfWatch('/tf_static')
        tf = dict((ns, (TfWatch(ns + '/tf'), TfWatch(ns + '/tf_static')))
                  for ns in robots)
        watches = dict((ns, RobotWatch(ns)) for ns in robots)
        starts = dict((ns, w.wait_for_truth()) for ns, w in watches.items())
        courses = dict((ns, CourseProcess(ns=ns, remaps=OWN_TF, params={
            'precise': str(bool(rospy.get_param('~precise', False))).lower(),
            'tf_timeout': float(rospy.get_param('~tf_timeout', 1.0)),
            'goal_distance': float(rospy.get_param('~goal_distance', 1.0)),
            'odom_frame': ns + '/odom',
            'base_frame': ns + '/base_footprint'})) for ns in robots)
        try:
            for ns in robots:
                try:
                    check_completed_course(self, watches[ns], courses[ns],
                                           starts[ns])
                except AssertionError:
                    # The simulator's own account of a starved CPU, if any.
                    with rosout.lock:
                        behind = [m.msg for m in rosout.records
                                  if m.name == '/fake_fleet'
                                  and 'skipping ahead' in m.msg]
                    print('%s failed; fake_fleet: %s' % (ns, behind or 'kept up'))
                    raise
                self.assertIn('Following tf %s/odom -> %s/base_footprint'
                              % (ns, ns), courses[ns].output)
        finally:
            for course in courses.values():
                course.cleanup()
        for ns in robots:
            moving, static = tf[ns]
            self.assertGreater(moving.count, 0, '%s/tf: no messages' % ns)
            self.assertEqual(moving.pairs, {('%s/odom' % ns,
                                             '%s/base_footprint' % ns)})
            self.assertEqual(static.pairs, {('world', '%s/odom' % ns)})
        self.assertEqual((shared[0].count, shared[1].count), (0, 0),
                         'something published on /tf or /tf_static')
        published = [name for name, _ in rospy.get_published_topics()]
        self.assertNotIn('/tf', published)
        self.assertNotIn('/tf_static', published)


if __name__ == '__main__':
    rospy.init_node('fake_fleet_test')
    rostest.rosrun('rbx1_nav', 'fake_fleet_test', FakeFleetTest)
