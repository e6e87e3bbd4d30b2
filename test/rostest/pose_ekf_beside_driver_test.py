#!/usr/bin/env python3
"""rostest: pose_ekf beside a driver that publishes its transform too, and
a sensor that never comes (pose_ekf_beside_driver.test).

The test starts each pose_ekf as rosrun does and reads its output, so it sees
every line from the first, each with the ROS time it was logged at
(simulated seconds); delays are measured from pose_ekf's start-up line.
After its error or warning each pose_ekf must go on publishing, and end
with status 0 on Ctrl-C.
"""
import os
import re
import signal
import subprocess
import sys
import threading
import unittest

import rospy
import rostest
from geometry_msgs.msg import PoseWithCovarianceStamped
from std_srvs.srv import Trigger
from tf2_msgs.msg import TFMessage

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))
from rosrun import rosrun  # noqa: E402

START_LINE = 'at its default (--help lists them)'  # the start-up line
CONFLICT = 'also publishes the transform'
# rospy's console format: "[LEVEL] [wall]: text" or "[LEVEL] [wall, ros]: text".
LOG_LINE = re.compile(r'^\[\s*(\w+)\]\s*\[([\d.]+)(?:,\s*([\d.]+))?\]:\s?(.*)$')


class EkfProcess(object):
    """pose_ekf.py as rosrun starts it; its log lines as (level, ROS time, text)."""

    def __init__(self, ns, name, args):
        self.name = '/%s/%s' % (ns, name)
        self.lock = threading.Lock()
        self.lines = []
        self.proc = subprocess.Popen(
            rosrun('rbx1_nav', 'pose_ekf.py', '__name:=' + name,
                   '__ns:=' + ns, *args.split()),
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
            universal_newlines=True)
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self):
        for raw in self.proc.stdout:
            match = LOG_LINE.match(raw.rstrip())
            if match:
                level, wall, ros, text = match.groups()
                with self.lock:
                    self.lines.append((level, float(ros or wall), text))

    def find(self, text, level=None):
        with self.lock:
            return [(lvl, t, line) for lvl, t, line in self.lines
                    if text in line and (level is None or lvl == level)]

    def wait_for(self, text, count=1, level=None, wall_limit=60.0):
        """The first ``count`` lines with ``text``, waiting (wall) for them."""
        for _ in range(int(wall_limit / 0.05)):
            found = self.find(text, level)
            if len(found) >= count or self.proc.poll() is not None:
                break
            rospy.rostime.wallsleep(0.05)
        found = self.find(text, level)
        if len(found) < count:
            raise AssertionError('%s logged %d of %d lines with %r; output:\n%s'
                                 % (self.name, len(found), count, text,
                                    '\n'.join(l[2] for l in self.lines)))
        return found[:count]

    def interrupt(self, wall_limit=30.0):
        """Ctrl-C, as a user at the terminal; the exit status (None: it
        still ran ``wall_limit`` wall seconds later, and was killed)."""
        self.proc.send_signal(signal.SIGINT)
        try:
            return self.proc.wait(wall_limit)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
            return None

    def close(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            self.proc.wait()


class Combined(object):
    """The stamps (ROS s) of one filter's odom_combined, as they arrive."""

    def __init__(self, ns, ekf):
        self.lock = threading.Lock()
        self.stamps = []
        rospy.Subscriber('/%s/%s/odom_combined' % (ns, ekf),
                         PoseWithCovarianceStamped, self.on_combined)

    def on_combined(self, msg):
        with self.lock:
            self.stamps.append(msg.header.stamp.to_sec())

    def between(self, start, end):
        with self.lock:
            return [t for t in self.stamps if start < t <= end]

    def last(self):
        with self.lock:
            return self.stamps[-1] if self.stamps else None


class TfWatch(object):
    """Callers of tf messages carrying ``child``, and odom_combined counts."""

    def __init__(self, ns, child, ekf):
        self.lock = threading.Lock()
        self.child = child
        self.callers = {}
        self.combined = 0
        rospy.Subscriber('/%s/tf' % ns, TFMessage, self.on_tf, queue_size=200)
        rospy.Subscriber('/%s/%s/odom_combined' % (ns, ekf),
                         PoseWithCovarianceStamped, self.on_combined)

    def on_tf(self, msg):
        caller = msg._connection_header['callerid']
        with self.lock:
            for tf in msg.transforms:
                if tf.child_frame_id == self.child:
                    self.callers[caller] = self.callers.get(caller, 0) + 1

    def on_combined(self, _msg):
        with self.lock:
            self.combined += 1

    def reset(self):
        with self.lock:
            self.callers, self.combined = {}, 0


class PoseEkfBesideDriverTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        get = rospy.get_param
        cls.dup_ns, cls.est_ns = get('~dup_ns'), get('~estimator_ns')
        cls.driver, ekf = get('~driver'), get('~ekf')
        cls.wall = float(get('~timeout'))
        cls.tf = TfWatch(cls.est_ns, 'base_footprint', ekf)
        cls.combined = {cls.dup_ns: Combined(cls.dup_ns, ekf),
                        cls.est_ns: Combined(cls.est_ns, ekf)}
        cls.dup = EkfProcess(cls.dup_ns, ekf, get('~dup_args'))
        cls.est = EkfProcess(cls.est_ns, ekf, get('~estimator_args'))

    @classmethod
    def tearDownClass(cls):
        cls.dup.close()
        cls.est.close()

    def test_second_tf_publisher_is_named(self):
        # (The repeat every 30 s is OtherPublisherWatch's, unit-tested in
        # test/unit/test_pose_ekf_sensors.py.)
        driver = '/%s/%s' % (self.dup_ns, self.driver)
        within = float(rospy.get_param('~error_within'))
        (_, start, _), = self.dup.wait_for(START_LINE, wall_limit=self.wall)
        (_, stamp, line), = self.dup.wait_for(CONFLICT, 1, 'ERROR', self.wall)
        delay = stamp - start
        print('second tf publisher: error %.2f s after start-up: %s'
              % (delay, line), flush=True)
        self.assertIn('node %s also publishes' % driver, line)
        self.assertIn('publish_tf: false', line)
        self.assertLessEqual(delay, within)

    def test_estimator_only_leaves_tf_to_the_driver(self):
        driver = '/%s/%s' % (self.est_ns, self.driver)
        self.est.wait_for(START_LINE, wall_limit=self.wall)
        for _ in range(int(self.wall / 0.05)):
            if self.tf.combined or rospy.is_shutdown():
                break
            rospy.rostime.wallsleep(0.05)
        self.assertGreater(self.tf.combined, 0, 'no odom_combined')
        self.tf.reset()
        rospy.sleep(float(rospy.get_param('~watch_time')))
        with self.tf.lock:
            callers, combined = dict(self.tf.callers), self.tf.combined
        print('estimator only: base_footprint on tf from %s; %d odom_combined'
              % (callers, combined), flush=True)
        self.assertEqual(list(callers), [driver])
        self.assertGreater(combined, 0)
        self.assertEqual(self.est.find(CONFLICT), [])

    def test_missing_sensor_is_named_with_its_topic(self):
        topic = rospy.get_param('~missing_topic')
        slack = float(rospy.get_param('~warning_slack'))
        (_, start, _), = self.est.wait_for(START_LINE, wall_limit=self.wall)
        timeout = float(rospy.get_param(self.est.name + '/sensor_timeout'))
        text = 'no message came on %s' % topic
        (level, stamp, line), = self.est.wait_for(text, wall_limit=self.wall)
        delay = stamp - start
        print('missing sensor: warning %.2f s after start-up (timeout %.1f s):'
              ' %s' % (delay, timeout, line), flush=True)
        self.assertEqual(level, 'WARN')
        self.assertIn('nothing publishes %s' % topic, line)
        self.assertLessEqual(delay, timeout + slack)
        # The status service says what the filter waits for.
        service = self.est.name + '/get_status'
        rospy.wait_for_service(service, self.wall)
        status = rospy.ServiceProxy(service, Trigger)().message
        print('get_status:\n' + status, flush=True)
        self.assertIn('state: running; never received: imu', status)
        self.assertIn('imu on %s' % topic, status)
        self.assertIn('odom on /%s/odom' % self.est_ns, status)
        self.assertIn('covariance (x, y, yaw)', status)
        self.assertIn('tf off', status)
        self.assertEqual(len(self.est.find(text)), 1, 'warned more than once')

    def test_warned_filters_go_on_and_exit_0_on_ctrl_c(self):
        # unittest runs a class's tests in the order of their names: this
        # one stops both filters, so its name sorts last.
        # After its warning each filter publishes odom_combined at ~freq
        # for the watch_time after it: the first within first_output s (the
        # dup's error comes at start-up, before its first estimate), then
        # no gap longer than two steps to the window's end. Ctrl-C then
        # ends each with status 0.
        watch = float(rospy.get_param('~watch_time'))
        first_limit = float(rospy.get_param('~first_output'))
        topic = rospy.get_param('~missing_topic')
        (_, error, _), = self.dup.wait_for(CONFLICT, 1, 'ERROR', self.wall)
        (_, warning, _), = self.est.wait_for('no message came on %s' % topic,
                                             wall_limit=self.wall)
        for ns, proc, since in ((self.dup_ns, self.dup, error),
                                (self.est_ns, self.est, warning)):
            combined = self.combined[ns]
            freq = float(rospy.get_param(proc.name + '/freq', 30.0))  # its default
            end = since + watch
            for _ in range(int(self.wall / 0.05)):  # a second (ROS) past the end at most
                if ((combined.last() or 0.0) >= end or rospy.get_time() > end + 1.0
                        or rospy.is_shutdown()):
                    break
                rospy.rostime.wallsleep(0.05)
            stamps = combined.between(since, end)
            self.assertTrue(stamps, '%s: no odom_combined after its warning' % proc.name)
            first = stamps[0] - since
            gap = max(b - a for a, b in zip(stamps, stamps[1:] + [end]))
            print('%s: %d odom_combined in the %.1f s after its warning at '
                  '%.2f s (at %g Hz), the first %.3f s after it, longest gap '
                  'then %.3f s' % (proc.name, len(stamps), watch, since, freq,
                                   first, gap), flush=True)
            self.assertLessEqual(first, first_limit, proc.name)
            self.assertLessEqual(gap, 2.0 / freq, proc.name)
            self.assertGreaterEqual(len(stamps), (watch - first) * freq - 1, proc.name)
        for proc in (self.dup, self.est):
            status = proc.interrupt()
            print('%s: exit status %s on SIGINT' % (proc.name, status), flush=True)
            self.assertEqual(status, 0, '%s exited %s on SIGINT; output:\n%s' % (
                proc.name, status, '\n'.join(l[2] for l in proc.lines)))


if __name__ == '__main__':
    rospy.init_node('pose_ekf_beside_driver_test')
    rostest.rosrun('rbx1_nav', 'pose_ekf_beside_driver',
                   PoseEkfBesideDriverTest)
