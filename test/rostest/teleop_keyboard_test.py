#!/usr/bin/env python3
"""The keyboard teleop driven through a real pseudo-terminal.

Run by teleop_keyboard.test. The node runs through rosrun with its stdin,
stdout and stderr on the slave side of a pty that is its controlling
terminal (as in a terminal window); the test types on the master side and
watches cmd_vel. It checks the keys, the key-release timeout, and that every
way out (the quit key, SIGINT, the terminal closing) leaves a zero Twist as
the last message and the terminal as it was. Without a terminal, or with bad
parameters, the node must exit 1 and say why.

Waits poll with deadlines (~wall_limit); no wall-clock upper bound is
asserted, only the lower bound of the key timeout, which load cannot break.
"""
import os
import select
import signal
import subprocess
import termios
import threading
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist

READY = 'waiting for a key'  # the status line once the keyboard is live
# Not the node's default name: rostest names this test node after its
# test-name, teleop_keyboard, and a second node of that name would end it.
NODE_NAME = 'teleop_under_test'


def is_zero(twist):
    return not any((twist.linear.x, twist.linear.y, twist.linear.z,
                    twist.angular.x, twist.angular.y, twist.angular.z))


def wait_until(predicate, wall_limit):
    """Poll ``predicate`` every 10 ms; True as soon as it holds."""
    deadline = time.monotonic() + wall_limit
    while time.monotonic() < deadline:
        if predicate():
            return True
        rospy.rostime.wallsleep(0.01)
    return bool(predicate())


class CmdVelWatch(object):
    """Every cmd_vel Twist, with the monotonic time it arrived."""

    def __init__(self):
        self.lock = threading.Lock()
        self.messages = []
        self.sub = rospy.Subscriber('cmd_vel', Twist, self._on_cmd)

    def _on_cmd(self, msg):
        with self.lock:
            self.messages.append((time.monotonic(), msg))

    def since(self, start):
        with self.lock:
            return list(self.messages[start:])

    def count(self):
        with self.lock:
            return len(self.messages)

    def connected(self):
        return self.sub.get_num_connections() > 0


class TeleopOnPty(object):
    """teleop_keyboard.py through rosrun on a fresh pty, its output kept."""

    def __init__(self, params):
        self.master, self.slave = os.openpty()
        self.before = termios.tcgetattr(self.slave)
        self.chunks = []
        self.closing = threading.Event()
        # setsid -c: a new session with the pty as controlling terminal, as
        # a terminal window gives; setsid and rosrun exec, so the pid is the
        # node's.
        args = ['setsid', '-c', 'rosrun', 'rbx1_nav', 'teleop_keyboard.py',
                '__name:=' + NODE_NAME]
        args += ['_%s:=%s' % item for item in sorted(params.items())]
        self.proc = subprocess.Popen(args, stdin=self.slave, stdout=self.slave,
                                     stderr=self.slave, close_fds=True)
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self):
        # Drain the screen all along: a full pty would block the node.
        while not self.closing.is_set():
            try:
                if select.select([self.master], [], [], 0.1)[0]:
                    data = os.read(self.master, 4096)
                    if not data:
                        return
                    self.chunks.append(data)
            except (OSError, ValueError):  # pty closed
                return

    @property
    def screen(self):
        return b''.join(self.chunks).decode('utf-8', 'replace')

    def type(self, keys):
        os.write(self.master, keys.encode())

    def lflag(self):
        return termios.tcgetattr(self.slave)[3]

    def wait(self, wall_limit):
        """The exit status; None if still running after ``wall_limit`` s."""
        wait_until(lambda: self.proc.poll() is not None, wall_limit)
        return self.proc.poll()

    def hang_up(self):
        """Close both ends, as closing a terminal window does (once)."""
        if self.closing.is_set():
            return
        self.closing.set()
        self.reader.join()  # before the fds close and their numbers are reused
        os.close(self.master)
        os.close(self.slave)

    def close(self):
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()
        self.hang_up()


class TeleopKeyboardTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.params = dict(
            (name, float(rospy.get_param('~' + name)))
            for name in ('linear_speed', 'angular_speed', 'key_timeout',
                         'rate'))
        cls.limit = float(rospy.get_param('~wall_limit'))
        cls.tol = float(rospy.get_param('~speed_tolerance'))
        cls.long_timeout = float(rospy.get_param('~long_key_timeout'))
        cls.watch = CmdVelWatch()

    def start(self, **params):
        node = TeleopOnPty(dict(self.params, **params))
        self.addCleanup(node.close)
        self.assertTrue(wait_until(lambda: READY in node.screen
                                   or node.proc.poll() is not None,
                                   self.limit), node.screen)
        self.assertIsNone(node.proc.poll(), node.screen)
        self.assertTrue(wait_until(self.watch.connected, self.limit),
                        'teleop never connected to cmd_vel')
        return node

    def next_message(self, start, matches, what):
        """The first Twist from message ``start`` on that ``matches``."""
        found = []

        def arrived():
            found[:] = [m for m in self.watch.since(start) if matches(m[1])]
            return found
        self.assertTrue(wait_until(arrived, self.limit), 'no %s' % what)
        return found[0]

    def press(self, node, key, matches, what):
        start = self.watch.count()
        sent = time.monotonic()
        node.type(key)
        return sent, start, self.next_message(start, matches, what)

    def moving_forward(self, twist):
        return (abs(twist.linear.x - self.params['linear_speed']) < self.tol
                and twist.angular.z == 0.0)

    def assert_stopped_and_gone(self, node):
        """The node's connection closed; its last Twist was a zero."""
        self.assertTrue(wait_until(lambda: not self.watch.connected(),
                                   self.limit), 'cmd_vel still connected')
        last = self.watch.since(0)[-1][1]
        self.assertTrue(is_zero(last), 'last cmd_vel was %s' % last)

    def assert_moving_until(self, start, moment):
        """Every Twist from ``start`` up to ``moment`` was a motion."""
        before = [m for t, m in self.watch.since(start) if t <= moment]
        self.assertTrue(before and not any(is_zero(m) for m in before),
                        'the robot had stopped before the test ended it')

    def assert_terminal_restored(self, node):
        after = termios.tcgetattr(node.slave)
        for flag in ('ECHO', 'ICANON', 'ISIG'):
            self.assertTrue(after[3] & getattr(termios, flag),
                            '%s still off after the node exited' % flag)
        self.assertEqual(after, node.before)

    def test_keys_timeout_and_quit(self):
        node = self.start()
        # While the node runs, the terminal is in its key-by-key mode.
        self.assertFalse(node.lflag() & (termios.ECHO | termios.ICANON))

        self.press(node, 'i', self.moving_forward, "'i': forward Twist")
        _, _, (_, left) = self.press(node, 'j', lambda m: m.angular.z > 0,
                                     "'j': left turn")
        self.assertAlmostEqual(left.angular.z, self.params['angular_speed'],
                               delta=self.tol)
        self.assertEqual(left.linear.x, 0.0)
        self.press(node, 'k', is_zero, "'k': zero Twist")

        # One 'i', then no key: repeats at ~rate, then a zero by itself.
        sent, start, _ = self.press(node, 'i', self.moving_forward, 'motion')
        stopped, _ = self.next_message(start, is_zero, 'zero after timeout')
        after = self.watch.since(start)
        motion = [m for t, m in after if t < stopped]
        print('RESULT key timeout: zero %.3f s after the key (>= %.3f); '
              '%d motion messages before it' % (stopped - sent,
                                                self.params['key_timeout'],
                                                len(motion)))
        # Exact, not a timing tolerance: the node saw the key after `sent`
        # and the zero arrived after the node decided to stop.
        self.assertGreaterEqual(stopped - sent, self.params['key_timeout'])
        self.assertTrue(all(self.moving_forward(m) for m in motion))
        self.assertGreaterEqual(len(motion), 2, 'the command was not repeated')

        # Quit while moving.
        self.press(node, 'i', self.moving_forward, 'motion before quit')
        node.type('Q')
        status = node.wait(self.limit)
        self.assertEqual(status, 0, node.screen)
        self.assert_stopped_and_gone(node)
        self.assert_terminal_restored(node)

    # In the next two, a key timeout longer than any wait keeps the robot
    # moving until the signal: only the node's exit path can stop it.

    def test_sigint_stops_and_restores_the_terminal(self):
        node = self.start(key_timeout=self.long_timeout)
        _, start, _ = self.press(
            node, 'u', lambda m: m.linear.x > 0 and m.angular.z > 0,
            "'u': forward-left Twist")
        signalled = time.monotonic()
        node.proc.send_signal(signal.SIGINT)
        self.assertEqual(node.wait(self.limit), 0, node.screen)
        self.assert_moving_until(start, signalled)
        self.assert_stopped_and_gone(node)
        self.assert_terminal_restored(node)

    def test_terminal_closed_stops_the_robot(self):
        node = self.start(key_timeout=self.long_timeout)
        _, start, _ = self.press(node, ',', lambda m: m.linear.x < 0,
                                 "',': backward Twist")
        closed = time.monotonic()
        node.hang_up()  # the node gets SIGHUP, and EIO from its terminal
        self.assertEqual(node.wait(self.limit), 0)
        self.assert_moving_until(start, closed)
        self.assert_stopped_and_gone(node)

    def test_refuses_to_run_without_a_terminal(self):
        # No master at this address: the check must come before init_node,
        # which would otherwise wait for a master forever.
        env = dict(os.environ, ROS_MASTER_URI='http://localhost:1/')
        proc = subprocess.run(['rosrun', 'rbx1_nav', 'teleop_keyboard.py'],
                              stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, env=env,
                              universal_newlines=True, timeout=self.limit)
        self.assertEqual(proc.returncode, 1, proc.stdout)
        self.assertIn('needs a keyboard', proc.stdout)
        self.assertIn('terminal', proc.stdout)
        self.assertEqual(len(proc.stdout.strip().splitlines()), 1, proc.stdout)

    def test_bad_parameter_exits_1_and_leaves_the_terminal_alone(self):
        node = TeleopOnPty(dict(self.params, linear_speed=5.0))
        self.addCleanup(node.close)
        self.assertEqual(node.wait(self.limit), 1, node.screen)
        self.assertTrue(wait_until(lambda: '~linear_speed' in node.screen,
                                   self.limit), node.screen)
        self.assertEqual(termios.tcgetattr(node.slave), node.before)


if __name__ == '__main__':
    rospy.init_node('teleop_keyboard_test')
    rostest.rosrun('rbx1_nav', 'teleop_keyboard', TeleopKeyboardTest)
