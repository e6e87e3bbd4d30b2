#!/usr/bin/env python3
"""ROS time jumps back: pose_ekf and odom_ekf say so and go on at once.

Run by pose_ekf_time_jump.test. Once simulated time is past jump + 1 s
(so the new clock's start is positive), the test replaces sim_clock by one
that starts ~jump seconds earlier (a looping bag, a restarted simulator).
pose_ekf must publish odom_combined again within ~resume_within simulated
seconds of the new clock's start, odom_ekf must republish it on odom_ekf,
neither may publish a stamp older than its last one on the new clock, and
both must log "ROS time moved backwards by <jump> s".
"""
import os
import re
import subprocess
import sys
import tempfile
import threading
import unittest

import rospy
import rostest
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from course_harness import RosoutWatch, kill_node, wait_until  # noqa: E402
from rosrun import rosrun  # noqa: E402


class StampWatch(object):
    """Every header stamp (s) received on one topic, in arrival order."""

    def __init__(self, topic, msg_type):
        self.lock = threading.Lock()
        self.stamps = []
        rospy.Subscriber(topic, msg_type, self._on_msg, queue_size=100)

    def _on_msg(self, msg):
        with self.lock:
            self.stamps.append(msg.header.stamp.to_sec())

    def latest(self):
        with self.lock:
            return self.stamps[-1] if self.stamps else None

    def mark(self):
        """Where the stamps received from now on start."""
        with self.lock:
            return len(self.stamps)

    def after_jump(self, mark, below):
        """The stamps received since ``mark`` from the first one under
        ``below`` (the first of the new clock) on."""
        with self.lock:
            for i in range(mark, len(self.stamps)):
                if self.stamps[i] < below:
                    return self.stamps[i:]
        return []


class TimeJumpTest(unittest.TestCase):

    def test_time_moving_backwards_restarts_the_filter_at_once(self):
        jump = float(rospy.get_param('~jump'))
        within = float(rospy.get_param('~resume_within'))
        speed = float(rospy.get_param('~speed'))
        ekf_node = rospy.get_param('~ekf_node')
        odom_ekf_node = rospy.get_param('~odom_ekf_node')
        log = RosoutWatch()
        fused = StampWatch('odom_combined', PoseWithCovarianceStamped)
        odom = StampWatch('odom_ekf', Odometry)
        self.assertTrue(wait_until(
            lambda: (fused.latest() or 0.0) > jump + 1.0),
            'no odom_combined past %.1f s of simulated time' % (jump + 1.0))
        marks = fused.mark(), odom.mark()
        kill_node('/sim_clock')
        before = fused.latest()
        back_to = before - jump
        new_clock = before - jump / 2  # stamps below this are the new clock's
        # Time on the new clock starts once both of the graph's lockstep
        # members have joined it, the simulator and pose_ekf (odom_ekf only
        # republishes): with the default, the simulator alone, time ran
        # 3.4 s on before pose_ekf had rejoined, beside two CPU burners.
        # Its output (who joined it, and when) goes into a failure's message.
        clock_log = tempfile.TemporaryFile(mode='w+')
        clock = subprocess.Popen(
            rosrun('rbx1_nav', 'sim_clock.py', '__name:=sim_clock',
             '_speed:=%g' % speed, '_start_time:=%.3f' % back_to, '_members:=2'),
            stdout=clock_log, stderr=subprocess.STDOUT)
        try:
            # Wait a simulated second past the allowance, so a late restart
            # shows as a late first stamp rather than as no stamp at all.
            # The new sim_clock starts in a few seconds, more on a loaded
            # machine; simulated time waits at its start for the simulator.
            wait_until(lambda: (odom.after_jump(marks[1], new_clock)
                                or [0.0])[-1] > back_to + within + 1.0)
        finally:
            clock.terminate()
            clock.wait()
            clock_log.seek(0)
            said = 'the restarted sim_clock said:\n' + clock_log.read()[-3000:]
            clock_log.close()
        fused_new = fused.after_jump(marks[0], new_clock)
        odom_new = odom.after_jump(marks[1], new_clock)
        ekf_line = log.find(ekf_node, 'ROS time moved backwards by')
        odom_line = log.find(odom_ekf_node, 'ROS time moved backwards by')
        # Where the test struck depends on when its wall-clock poll saw the
        # filter past jump + 1 s: the two clock figures, and the jumps the
        # nodes logged (their difference), are wall-timed.
        jumps = [re.search(r'moved backwards by ([\d.]+) s', line.msg) if line else None
                 for line in (ekf_line, odom_line)]
        print('RESULT time_jump: clock killed at %.3f s (wall-timed) and started '
              'again at %.3f s (wall-timed); first odom_combined '
              '%.3f s after the new start, first odom_ekf %.3f s; jump logged by '
              'pose_ekf %s s (wall-timed), by odom_ekf %s s (wall-timed)'
              % ((before, back_to,
                  fused_new[0] - back_to if fused_new else float('nan'),
                  odom_new[0] - back_to if odom_new else float('nan'))
                 + tuple(found.group(1) if found else 'none' for found in jumps)))
        self.assertTrue(fused_new, 'pose_ekf published nothing on the new clock; ' + said)
        self.assertLessEqual(fused_new[0] - back_to, within, said)
        self.assertTrue(odom_new, 'odom_ekf republished nothing on the new clock; ' + said)
        self.assertLessEqual(odom_new[0] - back_to, within, said)
        for name, stamps in (('odom_combined', fused_new), ('odom_ekf', odom_new)):
            self.assertTrue(all(b > a for a, b in zip(stamps, stamps[1:])),
                            '%s went back in time on the new clock' % name)
        for node, line, found in zip((ekf_node, odom_ekf_node), (ekf_line, odom_line), jumps):
            self.assertIsNotNone(line, '%s did not log the time jump' % node)
            self.assertIsNotNone(found, line.msg)
            self.assertAlmostEqual(float(found.group(1)), jump, delta=1.0)
            self.assertIn('a bag looping or the simulator restarted? '
                          'Restarting from the next readings', line.msg)


if __name__ == '__main__':
    rospy.init_node('pose_ekf_time_jump_test')
    rostest.rosrun('rbx1_nav', 'pose_ekf_time_jump', TimeJumpTest)
