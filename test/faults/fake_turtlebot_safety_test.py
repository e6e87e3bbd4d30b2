#!/usr/bin/env python3
"""rostest: the fake TurtleBot survives absurd and non-finite commands.

Speeds of 1e9 are clamped to the limits; a NaN or infinite command is taken
as a stop (well before the watchdog would act); a 1 kHz flood of such
commands neither slows the simulation nor floods the log; no input ever
makes the published pose non-finite. With a node left publishing on
cmd_vel (left_running, started for the flood), the flooding test node is
a second publisher: the robot names both, once. Limits are read from the
node's parameters.
"""
import itertools
import math
import os
import subprocess
import sys
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from rosgraph_msgs.msg import Log

from rbx1_nav.sim.params import WARN_PERIOD

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from fake_turtlebot_recorder import Recorder, motion_episode, planar, wait_for  # noqa: E402

PKG = 'rbx1_nav'
NODE = 'fake_turtlebot/'
INF, NAN = float('inf'), float('nan')
FLOOD = 2.0  # wall s of the 1 kHz flood


def twists_after(rec, t, topic='odom'):
    """(stamp, v, w) of every ``topic`` message stamped after ``t``
    (topic 'truth': the simulator's true speeds, exactly as executed)."""
    return [(r[0], r[4], r[5]) for r in map(planar, rec.snapshot(topic)) if r[0] > t]


class Safety(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('fake_turtlebot_safety_test')
        cls.max_v = rospy.get_param(NODE + 'max_linear_speed')
        cls.max_w = rospy.get_param(NODE + 'max_angular_speed')
        cls.timeout = rospy.get_param(NODE + 'cmd_timeout')
        cls.stop_within = rospy.get_param('~stop_within', 0.5)
        cls.rec = Recorder()
        assert wait_for(lambda: len(cls.rec.snapshot('odom')) > 5, 30.0, wall=True), 'no odom'

    def test_1_absurd_speeds_are_clamped(self):
        sent = self.rec.send(1e9, -1e9)
        self.assertTrue(self.rec.wait_stopped(sent, 10 * self.timeout + 60.0))
        k, j = motion_episode(self.rec.snapshot('odom'), sent)
        odom = self.rec.snapshot('odom')[k:j]
        self.assertTrue(odom)
        for v, w in (planar(m)[4:] for m in odom):  # rebuilt from wheel travel
            self.assertAlmostEqual(v, self.max_v, delta=1e-9)
            self.assertAlmostEqual(w, -self.max_w, delta=1e-9)
        moving = {m.header.stamp for m in odom}
        truth = [planar(m)[4:] for m in self.rec.snapshot('truth')
                 if m.header.stamp in moving]
        self.assertTrue(truth)
        self.assertTrue(all(vw == (self.max_v, -self.max_w) for vw in truth), truth)

    def test_2_non_finite_commands_stop_the_robot_at_once(self):
        for bad in [(NAN, 0.0), (0.1, INF), (-INF, NAN)]:
            sent = self.rec.send(0.2, 0.0)
            self.assertTrue(wait_for(lambda: any(v == 0.2 for _, v, _ in
                                                 twists_after(self.rec, sent)), 60.0))
            sent_bad = self.rec.send(*bad)
            self.assertTrue(wait_for(lambda: any(v == 0.0 for _, v, _ in
                                                 twists_after(self.rec, sent_bad)), 60.0), bad)
            self.assertTrue(wait_for(lambda: any(v == 0.0 for _, v, _ in twists_after(
                self.rec, sent_bad, 'truth')), 60.0), bad)
            after = twists_after(self.rec, sent, 'truth')
            moving = min(t for t, v, _ in after if v == 0.2)
            stopped = min(t for t, v, _ in after if t > moving and v == 0.0)
            self.assertLess(stopped - sent_bad, self.stop_within, bad)
            # The bad command stopped it, not the watchdog: the robot drove
            # at 0.2 m/s without a break until it stopped, and it stopped
            # less than cmd_timeout after the last good command was sent
            # (the watchdog acts cmd_timeout after that command arrived).
            self.assertTrue(all(v == 0.2 for t, v, _ in after if moving <= t < stopped),
                            (bad, after))
            self.assertLess(stopped - sent, self.timeout, bad)

    def test_3_a_1khz_flood_from_a_second_node_keeps_the_rate_and_is_named(self):
        warnings = []
        rospy.Subscriber('/rosout', Log, lambda m: m.name == '/fake_turtlebot'
                         and m.level >= Log.WARN and warnings.append(m), queue_size=10000)
        pub = rospy.Publisher('cmd_vel', Twist, queue_size=1000, tcp_nodelay=True)
        self.assertTrue(wait_for(lambda: pub.get_num_connections() > 0, 30.0, wall=True))
        left = subprocess.Popen(['rostopic', 'pub', '-r', '10',
                                 'cmd_vel', 'geometry_msgs/Twist', '{}',
                                 '__name:=left_running'])
        try:
            self._flood(pub, warnings)
        finally:
            left.terminate()
            left.wait()

    def _flood(self, pub, warnings):
        bad = itertools.cycle([(NAN, 0.0), (0.1, INF), (1e9, -1e9), (-INF, NAN), (0.1, 0.0)])

        def window(send):
            """Simulated seconds that pass in FLOOD wall seconds; commands sent."""
            start, wall, sent = rospy.Time.now(), time.monotonic(), 0
            while time.monotonic() - wall < FLOOD:
                if send:
                    msg = Twist()
                    msg.linear.x, msg.angular.z = next(bad)
                    pub.publish(msg)
                    sent += 1
                rospy.rostime.wallsleep(max(0.0, wall + sent * 1e-3 - time.monotonic()))
            return start.to_sec(), (rospy.Time.now() - start).to_sec(), sent

        _, quiet, _ = window(send=False)
        began, flooded, sent = window(send=True)
        stamps = [planar(m)[0] for m in self.rec.snapshot('odom')]
        during = [t for t in stamps if began <= t <= began + flooded]
        gaps = [b - a for a, b in zip(during, during[1:])]
        step = 1.0 / rospy.get_param(NODE + 'rate')
        publishers = [m for m in warnings if 'nodes publish on' in m.msg]
        flood_warnings = [m for m in warnings if m.header.stamp.to_sec() >= began
                          and m not in publishers]
        # Each kind (non-finite, clamped) at most once a WARN_PERIOD of ROS time.
        allowed = 2 * (math.ceil(flooded / WARN_PERIOD) + 1)
        print('RESULT 1 kHz flood: %d commands in %.1f s; simulated time advanced %.2f s '
              '(%.2f s in the same wall time before it); %d odom messages, largest gap '
              '%.3f s (step %.3f s); %d warnings (allowed %d)' % (
                  sent, FLOOD, flooded, quiet, len(during), max(gaps), step,
                  len(flood_warnings), allowed))
        # The simulator handled every command of the flood: each step
        # executed the clamped limits, the plain (0.1, 0) or a stop (a
        # non-finite command's, or left_running's), nothing else.
        flood_twists = [(v, w) for t, v, w in twists_after(self.rec, began, 'truth')
                        if t <= began + flooded]
        self.assertTrue(set(flood_twists) <= {(self.max_v, -self.max_w),
                                              (0.1, 0.0), (0.0, 0.0)},
                        set(flood_twists))
        # And it clamped more commands than it may warn about: each entry
        # into the clamped twist is a new clamped command received (it
        # holds the last command between them), so the throttle had more
        # to say than it said.
        clamped = (self.max_v, -self.max_w)
        entries = sum(1 for a, b in zip(flood_twists, flood_twists[1:])
                      if b == clamped and a != clamped)
        print('RESULT the simulator executed %d clamped commands in the flood' % entries)
        self.assertGreater(entries, allowed // 2)
        self.assertGreater(flooded, 0.5 * quiet)  # the simulation kept its pace
        self.assertLess(max(gaps), 1.5 * step)    # and published every step
        self.assertGreater(len(flood_warnings), 0)
        self.assertLessEqual(len(flood_warnings), allowed,
                             [m.msg for m in flood_warnings])
        # The robot names the two publishers once, within its look at the
        # master every few seconds (wall time).
        self.assertTrue(wait_for(lambda: any('nodes publish on' in m.msg for m in warnings),
                                 10.0, wall=True), [m.msg for m in warnings])
        named = [m.msg for m in warnings if 'nodes publish on' in m.msg]
        print('RESULT second publisher: %s' % named)
        self.assertEqual(len(named), 1, named)
        self.assertIn(rospy.get_name(), named[0])
        self.assertIn('/left_running', named[0])

    def test_4_pose_stays_finite_and_node_keeps_running(self):
        last = rospy.Time.now().to_sec()
        self.assertTrue(wait_for(lambda: twists_after(self.rec, last), 60.0))
        for topic in ('odom', 'truth'):
            msgs = self.rec.snapshot(topic)
            self.assertTrue(msgs, topic)
            for m in msgs:
                self.assertTrue(all(math.isfinite(c) for c in planar(m)), planar(m))


if __name__ == '__main__':
    rostest.rosrun(PKG, 'fake_turtlebot_safety', Safety, sys.argv)
