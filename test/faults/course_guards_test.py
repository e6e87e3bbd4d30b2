#!/usr/bin/env python3
"""Courses that must not say "Course complete": each ends with exit 1, the
robot stopped, and one line naming the cause and the fix.

Run by course_guards.test (driver, second_course, then typo, on one graph) and the
course_guard_*.test files beside it, each under lockstep at full speed
with the fake robot; ``~case`` picks the fault:

* ``driver``: another node (this test) publishes zeros on the course's
  cmd_vel from before it starts (a warning only: the course drives on),
  then, once the robot is under way, one command to move;
* ``two_publishers``: a second fake robot in namespace robot1 with the
  same frames on /tf (the .test starts both); the course in robot1
  follows a transform that two nodes publish, and each fake robot names
  the other;
* ``jump``: the fake robot publishes no tf; this test relays its odometry
  to tf, then adds 3 m to it once the robot is under way;
* ``second_course``: a course (nav_square) started while another
  (odom_out_and_back) drives the robot; the second must send nothing and
  exit 1 saying it left the robot to the first, which ends where the pure
  model of it alone ends;
* ``typo``: ``_goal_distnace:=0.5`` on the command line refuses to move
  and leaves the master's parameters as it found them (the fake robot's
  typo too); the same typo left on the master only warns (the course
  runs its default goal_distance, which nothing else sets); the .test
  also launches a node with the typo as a ``<param>``, which refuses too.

In driver, second_course, two_publishers and jump this test is a lockstep member, with
ticks of its own as a teleop node's at 10 Hz (``hold_ticks``): time waits
for it, so the course cannot end before the test has heard it and looked
(at full speed a course takes half a wall second, less than this node may
wait for the CPU on a loaded machine).
"""
import os
import re
import sys
import threading
import math
import unittest

import rosgraph
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import TransformStamped, Twist
from nav_msgs.msg import Odometry

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import (CourseProcess, RosoutWatch, RobotWatch,  # noqa: E402
                            is_zero, launched_node_status, wait_sim, wait_until)
from course_model import reference_end_pose  # noqa: E402
from rbx1_nav.msg import LockstepReport  # noqa: E402
from rbx1_nav.transform_utils import normalize_angle  # noqa: E402
from rbx1_nav.sim_time import member_ros as lockstep  # noqa: E402
from rbx1_nav.sim_time.member import ALIGN, aligned  # noqa: E402
from rbx1_nav.common.publish_ros import to_ns  # noqa: E402

#: A short course: one leg.
SHORT = {'legs': 1, 'goal_distance': 0.5, 'tf_timeout': 5.0}
#: odom_out_and_back.py's ~goal_distance when none is set (m).
DEFAULT_GOAL_DISTANCE = 1.0
#: A course's first line, logged once it has simulated time.
STARTED = 'parameter at its default'



class Commands(object):
    """Every message on a cmd_vel with the node that sent it."""

    def __init__(self, topic):
        self.lock = threading.Lock()
        self.heard = []  # (sender, Twist)
        self.topic = rospy.resolve_name(topic)
        rospy.Subscriber(topic, Twist, self._on_cmd, queue_size=1000)

    def hears(self, node):
        """True once this subscriber is connected to ``node``."""
        return node in lockstep.connected_publishers(self.topic)

    def _on_cmd(self, msg):
        with self.lock:
            self.heard.append((msg._connection_header['callerid'], msg))

    def last(self):
        with self.lock:
            return self.heard[-1] if self.heard else (None, None)

    def motion_from(self, node):
        with self.lock:
            return [m for who, m in self.heard if who == node and not is_zero(m)]


class CourseGuardsTest(unittest.TestCase):

    def assert_stopped_by(self, course, commands, watch):
        """The course's own zero Twist was the robot's last command, and
        the robot stands still by ground truth."""
        who, last = commands.last()
        self.assertEqual(who, course.node_name, 'last cmd_vel from %s: %s'
                         % (who, last))
        self.assertTrue(is_zero(last), 'last cmd_vel not a stop: %s' % last)
        wait_sim(0.5)
        self.assertEqual(watch.true_speed(), (0.0, 0.0), 'robot still moving')

    def one_error_line(self, course, text):
        """The course's output has exactly one line with ``text``; it,
        without the log's stamps (when it came depends on this node's
        wall clock, not on the course)."""
        lines = [line for line in course.output.splitlines() if text in line]
        self.assertEqual(len(lines), 1, course.output)
        return re.sub(r'^\[\w+\] \[[^]]*\]: ', '', lines[0])

    def course_in_lockstep(self, member, course_args):
        """A course started with this test a lockstep member (joined
        first, so time waits for it from the course's start)."""
        rospy.on_shutdown(member.leave)
        member.join(30.0)
        return CourseProcess(**course_args)

    def hold_ticks(self, member, course, commands, watch, at_tick):
        """This test's ticks as a lockstep member, at multiples of ALIGN
        (0.1 s, where the simulator has a step), as a teleop node's at
        10 Hz: time waits for it, so a course at full speed (half a wall
        second) cannot end before the test has looked. First it waits
        until ``commands`` is connected to the course (or the course has
        ended), to hear the course's last command; at each tick it awaits
        the simulator's ground truth at the tick, as a course awaits its
        transform, then calls ``at_tick()``, until that returns True or
        the course has ended."""
        self.assertTrue(wait_until(lambda: commands.hears(course.node_name)
                                   or not course.running(), 30.0),
                        'no connection to the course on %s' % commands.topic)
        for _, tick, _ in member.grants(rospy.get_name()):
            if tick % ALIGN == 0:
                self.assertTrue(wait_until(lambda: to_ns(
                    watch.truth.header.stamp) >= tick), 'no ground truth at the tick')
                if not course.running() or at_tick():
                    return
            member.report(tick, aligned(tick + 1))

    def test_guard(self):
        getattr(self, 'check_' + rospy.get_param('~case'))()

    # -- another node drives the robot -------------------------------------------
    def check_driver(self):
        me = rospy.get_name()
        watch = RobotWatch()
        commands = Commands('cmd_vel')
        start = watch.wait_for_truth()
        member = lockstep.Member()
        intruder = member.publisher(rospy.resolve_name('cmd_vel'), Twist)
        member.wait_for_inputs(30.0, me)  # the robot hears it before it joins
        course = self.course_in_lockstep(member, dict(params=SHORT))
        try:
            def at_tick():
                if watch.moved_since(start) > 0.1:
                    return True
                intruder.publish(Twist())  # a teleop node at rest: zeros
                return False
            self.hold_ticks(member, course, commands, watch, at_tick)
            self.assertTrue(watch.moved_since(start) > 0.1,
                            'the course ended before the robot moved 0.1 m:\n'
                            + course.output)
            self.assertTrue(course.running(), 'zeros ended the course:\n'
                            + course.output)
            move = Twist()
            move.linear.x = 0.1
            intruder.publish(move)
            member.leave()  # its report counts the move: the robot waits for it
            status = course.wait()
        finally:
            member.leave()
            course.cleanup()
        out = course.output
        line = self.one_error_line(course, 'commanded the robot on')
        print('RESULT driver exit=%d: %s' % (status, line))
        self.assertEqual(status, 1, out)
        self.assertIn('%s also publishes on /cmd_vel' % me, out)  # the warning
        self.assertIn('%s commanded the robot on /cmd_vel (0.1 m/s, 0 rad/s) '
                      'while this course drove it' % me, line)
        # This node also takes /cmd_vel (it hears the commands), as a driver's
        # process hosting a multiplexer does: killing it could kill the driver.
        self.assertIn('Stopped the robot. Fix: %s also takes this topic: most likely the '
                      'robot\'s velocity multiplexer' % me, line)
        self.assertIn('cmd_vel:=/cmd_vel_mux/input/navi', line)
        self.assertNotIn('rosnode kill', out)
        self.assertNotIn('Course complete', out)
        self.assertTrue(commands.motion_from(course.node_name), 'never drove')
        self.assert_stopped_by(course, commands, watch)

    # -- a second course while one drives ------------------------------------------
    def check_second_course(self):
        watch = RobotWatch()
        commands = Commands('cmd_vel')
        reporters = set()  # lockstep members heard reporting
        rospy.Subscriber(lockstep.REPORT_TOPIC, LockstepReport, lambda msg: reporters.add(
            msg._connection_header['callerid']), queue_size=100)
        start = watch.wait_for_truth()
        member = lockstep.Member()
        first = self.course_in_lockstep(member, dict(params=SHORT))
        second = []

        def clock_subscribed(node):
            return node in dict(rosgraph.Master(rospy.get_name()).getSystemState()[1]).get(
                '/clock', ())

        def at_tick():
            """Time waits at each tick while the second course starts, but for the ticks
            that bring it its first /clock; then until it takes part in lockstep, so it
            listens while the first drives however slowly it starts."""
            if not second:
                if watch.moved_since(start) < 0.1:
                    return False
                second.append(CourseProcess(script='nav_square.py', params={'rate': 20.0}))
            course = second[0]
            if course.node_name in reporters or not course.running():
                return False
            self.assertTrue(wait_until(lambda: clock_subscribed(course.node_name)
                                       or not course.running()), course.output)
            if not wait_until(lambda: STARTED in course.output or not course.running(), 0.2):
                return False  # a tick, and /clock with it
            self.assertTrue(wait_until(lambda: course.node_name in reporters
                                       or not course.running()), course.output)
            return False
        try:
            self.hold_ticks(member, first, commands, watch, at_tick)
            member.leave()
            status = first.wait()
            self.assertTrue(second, 'the first course ended before the robot moved 0.1 m:\n'
                            + first.output)
            refused = second[0].wait()
        finally:
            member.leave()
            first.cleanup()
            for course in second:
                course.cleanup()
        line = self.one_error_line(second[0], 'did not start')
        print('RESULT second_course exit=%d: %s' % (refused, line))
        self.assertEqual(refused, 1, second[0].output)
        self.assertIn('nav_square: did not start: /odom_out_and_back is driving the robot on '
                      '/cmd_vel (', line)
        self.assertIn('so this course left the robot to it and sent nothing. Run this again '
                      'when that course has ended; if it is stale (its terminal gone), stop it '
                      'first: rosnode kill /odom_out_and_back', line)
        self.assertNotIn('Course complete', second[0].output)
        self.assertEqual([m for who, m in commands.heard if who == second[0].node_name], [])
        # It did not start: its command line's _rate:=20.0 is not left on the master.
        names = rospy.get_param_names()
        self.assertEqual([n for n in names if n.startswith(second[0].node_name + '/')], [], names)
        # The first drove on and ended where it ends alone (the pure model; lockstep: 0.1 mm).
        self.assertEqual(status, 0, first.output)
        self.assertIn('Course complete', first.output)
        self.assertTrue(wait_until(watch.still), 'robot still moving after the course')
        end, alone = watch.pose(), reference_end_pose(SHORT)
        dx, dy = end.x - start.x, end.y - start.y
        c, s = math.cos(start.yaw), math.sin(start.yaw)
        along, across = c * dx + s * dy, -s * dx + c * dy
        error = math.hypot(along - alone.x, across - alone.y)
        turn = math.degrees(abs(normalize_angle(end.yaw - start.yaw - alone.yaw)))
        print('RESULT second_course: the first ended %.4f mm, %.4f deg from alone'
              % (error * 1e3, turn))
        self.assertLess(error, 1e-4)
        self.assertLess(turn, 0.01)

    # -- two robots, one transform -------------------------------------------------
    def check_two_publishers(self):
        rosout = RosoutWatch()
        watch = RobotWatch('robot1')
        commands = Commands('robot1/cmd_vel')
        watch.wait_for_truth()
        member = lockstep.Member()
        course = self.course_in_lockstep(member, dict(ns='robot1', params=SHORT))
        try:
            self.hold_ticks(member, course, commands, watch, lambda: False)
            member.leave()
            status = course.wait()
        finally:
            member.leave()
            course.cleanup()
        out = course.output
        line = self.one_error_line(course, 'comes from two nodes')
        print('RESULT two_publishers exit=%d: %s' % (status, line))
        self.assertEqual(status, 1, out)
        self.assertIn('tf odom -> base_footprint comes from two nodes, ', line)
        self.assertIn('/fake_turtlebot', line)
        self.assertIn('/robot1/fake_turtlebot', line)
        self.assertIn('Stopped the robot. Fix: give each robot its own frames '
                      '(e.g. _odom_frame:=robot1/odom', line)
        self.assertIn('/tf:=tf /tf_static:=tf_static', line)
        self.assertNotIn('Course complete', out)
        self.assert_stopped_by(course, commands, watch)
        # Each fake robot names the other (repeated every 30 simulated s).
        for robot, other in (('/fake_turtlebot', '/robot1/fake_turtlebot'),
                             ('/robot1/fake_turtlebot', '/fake_turtlebot')):
            self.assertTrue(wait_until(lambda: rosout.find(
                robot, 'node %s also publishes the transform odom -> '
                'base_footprint on /tf' % other)),
                '%s did not name %s' % (robot, other))

    # -- a jump no robot makes -----------------------------------------------------
    def check_jump(self):
        watch = RobotWatch()
        commands = Commands('cmd_vel')
        broadcaster = tf2_ros.TransformBroadcaster()
        offset = [0.0]

        def relay(msg):  # the odometry on tf, as a driver publishes it
            tf = TransformStamped()
            tf.header = msg.header
            tf.child_frame_id = msg.child_frame_id
            tf.transform.translation.x = msg.pose.pose.position.x + offset[0]
            tf.transform.translation.y = msg.pose.pose.position.y
            tf.transform.rotation = msg.pose.pose.orientation
            broadcaster.sendTransform(tf)

        rospy.Subscriber('odom', Odometry, relay, queue_size=100)
        start = watch.wait_for_truth()
        member = lockstep.Member()
        course = self.course_in_lockstep(member, dict(params=SHORT))
        try:
            self.hold_ticks(member, course, commands, watch,
                            lambda: watch.moved_since(start) > 0.1)
            self.assertTrue(course.running(), course.output)
            offset[0] = 3.0
            member.leave()
            status = course.wait()
        finally:
            member.leave()
            course.cleanup()
        out = course.output
        line = self.one_error_line(course, 'faster than the robot can')
        print('RESULT jump exit=%d: %s' % (status, line))
        self.assertEqual(status, 1, out)
        # 3 m between two updates 0.02 to 0.05 s apart (the relay's).
        self.assertRegex(line, r'tf odom -> base_footprint moved 3\.\d{3} m in '
                         r'0\.0\d s \(limit 0\.\d{3} m\), faster than the robot '
                         r'can at this course')
        self.assertIn("odometry reset (a restarted driver)? Stopped the robot. "
                      "Fix: give each robot its own frames", line)
        self.assertNotIn('Course complete', out)
        self.assert_stopped_by(course, commands, watch)

    # -- a typo ----------------------------------------------------------------------
    def check_typo(self):
        watch = RobotWatch()
        commands = Commands('cmd_vel')
        start = watch.wait_for_truth()
        # Set before the run by the user (rosparam set): legs, which the
        # command line gives too, and rate, which it does not.
        user = {'legs': 2, 'rate': 15}
        course = CourseProcess(params=dict(SHORT, goal_distnace=0.2), leftovers=user)
        status = course.finish()
        out = course.output
        line = self.one_error_line(course, 'unknown parameter')
        print('RESULT typo exit=%d: %s' % (status, line))
        self.assertEqual(status, 1, out)
        self.assertIn('unknown parameter ~goal_distnace (did you mean '
                      '~goal_distance?) on the command line; not starting', line)
        self.assertEqual(commands.motion_from(course.node_name), [])
        self.assertLess(watch.moved_since(start), 1e-9)
        self.assertEqual(watch.true_speed(), (0.0, 0.0))
        # The master's parameters as the refused run found them: nothing of
        # its command line (~goal_distnace, ~goal_distance, ...), the user's
        # legs and rate unchanged.
        left = rospy.get_param(course.node_name)
        print('RESULT typo: left on the master under %s: %s' % (course.node_name, left))
        self.assertEqual(left, user, out)

        # The launch file's <param> typo (launched by the .test): refused,
        # and the launch's parameters stay (roslaunch set them, not the node).
        launched, log = launched_node_status('odom_out_and_back_typo')
        print('RESULT typo in a launch file: exit %s' % launched)
        self.assertEqual(launched, 1, log)
        self.assertIn('unknown parameter ~goal_distnace (did you mean '
                      '~goal_distance?) in the launch file; not starting', log)
        self.assertEqual(rospy.get_param('/odom_out_and_back_typo'),
                         {'goal_distnace': 0.2, 'legs': 1})

        # The fake robot refused for a typo (another name: one runs)
        # leaves none of its command line either.
        robot = CourseProcess(script='fake_turtlebot.py', name='fake_turtlebot_typo',
                              params={'realistc': 'true'})
        status = robot.finish()
        self.assertEqual(status, 1, robot.output)
        self.assertIn('unknown parameter ~realistc', robot.output)
        self.assertFalse(rospy.has_param('/fake_turtlebot_typo'), rospy.get_param_names())

        # Left on the master by an earlier run, not on this command line:
        # a warning, and the course runs. Its command line sets no
        # goal_distance, so the leg it drives is the default's (1 m) unless
        # the leftover typo's 0.2 m took its place.
        before = watch.pose()
        unset = {key: value for key, value in SHORT.items() if key != 'goal_distance'}
        leftover = CourseProcess(name='leftover', leftovers={'goal_distnace': 0.2},
                                 params=dict(unset, goal_angle=0.3))
        status = leftover.finish()
        self.assertTrue(wait_until(watch.still), 'robot still moving after the course')
        drove = watch.moved_since(before)
        print('RESULT typo left on the master: exit %d, drove %.4f m by ground truth'
              % (status, drove))
        self.assertEqual(status, 0, leftover.output)
        self.assertIn('unknown parameter ~goal_distnace is ignored (did you mean '
                      '~goal_distance?)', leftover.output)
        self.assertIn('Course complete', leftover.output)
        # It drove the default goal_distance, not the leftover's 0.2: within
        # 1 cm by ground truth (a tick of the course at its default 0.15 m/s
        # and 20 Hz is 7.5 mm).
        self.assertLess(abs(drove - DEFAULT_GOAL_DISTANCE), 0.01, leftover.output)


if __name__ == '__main__':
    rospy.init_node('course_guards_test')
    rostest.rosrun('rbx1_nav', 'course_guards', CourseGuardsTest)
