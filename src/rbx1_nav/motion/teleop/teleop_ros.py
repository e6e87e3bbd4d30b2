"""The ROS side of teleop_keyboard.py: the terminal, one key at a time, and
the cmd_vel publisher, around rbx1_nav.motion.teleop.teleop's keyboard logic.

The robot is always sent a stop (a zero Twist, the last message), on a
quit key, Ctrl-C, a signal, rosnode kill, a closed terminal or an error,
and the terminal is restored.
"""
import atexit
import os
import select
import shutil
import signal
import sys
import termios
import threading
import time
import warnings

import rospy
from geometry_msgs.msg import Twist

from rbx1_nav.common import params, params_given
from rbx1_nav.common.cmd_vel_watch_ros import watch_publishers
from rbx1_nav.common.node_ros import (exit_if_help, init_node, keep_command_line,
                                      mend_rospy_shutdown, private_params, shut_down_on_signals)
from rbx1_nav.motion.teleop.teleop import NOT_A_TERMINAL, KeyboardTeleop, check_settings, help_text
from rbx1_nav.motion.course.command import STOP


class Keyboard(object):
    """The terminal on ``fd``, one key at a time, until :meth:`restore`.

    Echo, line editing and the signal keys are off (cbreak mode without
    ISIG), so Ctrl-C and Ctrl-Z arrive as keys; output processing stays on,
    so log lines still end their lines properly.
    """

    def __init__(self, fd):
        self.fd = fd
        self.saved = termios.tcgetattr(fd)
        atexit.register(self.restore)
        mode = termios.tcgetattr(fd)
        mode[0] &= ~termios.IXON  # Ctrl-S would freeze the screen
        mode[3] &= ~(termios.ECHO | termios.ICANON | termios.ISIG
                     | termios.IEXTEN)
        mode[6][termios.VMIN], mode[6][termios.VTIME] = 1, 0
        # TCSAFLUSH drops keys typed before now: they must not move the robot.
        termios.tcsetattr(fd, termios.TCSAFLUSH, mode)

    def read(self, timeout):
        """Keys typed within ``timeout`` s ('' if none); None once hung up."""
        if not select.select([self.fd], [], [], timeout)[0]:
            return ''
        try:
            data = os.read(self.fd, 64)
        except OSError:  # EIO: the terminal is gone
            return None
        return data.decode('latin-1') or None

    def restore(self):
        """Put the terminal back as it was; safe to call more than once."""
        saved, self.saved = self.saved, None
        if saved is not None:
            try:
                termios.tcsetattr(self.fd, termios.TCSADRAIN, saved)
            except termios.error:
                pass  # the terminal is gone: nothing to restore


class TeleopKeyboard(object):
    """Keys in, cmd_vel out, and a stop as the very last message."""

    def __init__(self, settings):
        self.teleop = KeyboardTeleop.from_settings(settings)
        self.period = rospy.Duration(1.0 / settings['rate'])
        # No queue_size: publish() writes in the calling thread, so the stop
        # from the shutdown hook is sent before rospy closes the connection
        # (a queued publisher's thread may not get to it).
        with warnings.catch_warnings():
            warnings.simplefilter('ignore', SyntaxWarning)
            self.cmd_vel = rospy.Publisher('cmd_vel', Twist, tcp_nodelay=True)
        # Shutdown hooks run in a thread of their own (a signal's too, see
        # main), so the stop waits for a publish in progress and goes after.
        self.lock = threading.Lock()
        self.stopped = False
        self.shown = None
        rospy.on_shutdown(self.stop)

    def publish(self, command):
        with self.lock:
            if not self.stopped:
                twist = Twist()
                twist.linear.x, twist.angular.z = command
                self.cmd_vel.publish(twist)

    def stop(self):
        """Send the final zero Twist; nothing is published after it."""
        with self.lock:
            if not self.stopped:
                self.stopped = True
                self.cmd_vel.publish(Twist())

    def show(self, text):
        """Redraw the status line (one line per change if not a terminal)."""
        if text == self.shown:
            return
        self.shown = text
        try:
            if sys.stdout.isatty():
                width = shutil.get_terminal_size().columns
                sys.stdout.write('\r%s\x1b[K' % text[:width - 1])
            else:
                sys.stdout.write(text + '\n')
            sys.stdout.flush()
        except OSError:
            pass  # the terminal is gone; the loop ends at the next read

    def run(self, keyboard):
        """Read keys and publish until a quit, a hang-up or a shutdown.

        The key-release timeout uses time.monotonic(): it is about a human
        at a keyboard, whose key repeats come in wall time whatever the ROS
        clock does. The cmd_vel repeat uses ROS time, like every rate here.
        """
        teleop, sent, next_send = self.teleop, STOP, rospy.Time(0)
        self.show(teleop.status())
        while not rospy.is_shutdown() and not teleop.quit:
            wait = teleop.read_timeout(
                time.monotonic(), (next_send - rospy.Time.now()).to_sec())
            keys = keyboard.read(wait)
            command = teleop.feed(keys, time.monotonic())
            ros_now = rospy.Time.now()
            if command != sent or (teleop.moving and ros_now >= next_send):
                self.publish(command)
                sent, next_send = command, ros_now + self.period
            self.show(teleop.status())


def main(specs, doc):
    """main() of teleop_keyboard.py (``specs``: its parameters, ``doc``: its
    docstring, for --help); returns the process exit status."""
    exit_if_help(specs, doc)
    # Before init_node, so that it also says so without a master.
    if not os.isatty(0):
        sys.stderr.write(NOT_A_TERMINAL + '\n')
        return 1
    # Closing the terminal window (SIGHUP) must stop the robot too.
    shut_down_on_signals((signal.SIGINT, signal.SIGTERM, signal.SIGHUP))
    mend_rospy_shutdown()
    if not init_node('teleop_keyboard'):
        return 0  # quit while starting: as after a quit
    try:
        given, before = private_params()
        settings = check_settings(params_given.layered(given, before), rospy.get_name(), given)
    except (ValueError, rospy.ROSInitException) as err:
        rospy.logerr('teleop_keyboard: bad parameters, not starting: %s', err)
        return 1
    keep_command_line(given, before)
    rospy.loginfo('teleop_keyboard: publishing %s; %s', rospy.resolve_name(
        'cmd_vel'), params.start_text(specs, settings))
    node = TeleopKeyboard(settings)
    watch_publishers('teleop_keyboard', [node.cmd_vel.resolved_name],
                     own=rospy.get_name())
    keyboard = Keyboard(0)
    try:
        print(help_text(settings['key_timeout']))
        node.run(keyboard)
        return 0
    except Exception as err:  # log it, stop the robot, exit non-zero
        keyboard.restore()
        rospy.logerr('teleop_keyboard: %s: %s; stopping the robot',
                     type(err).__name__, err, exc_info=True)
        return 1
    finally:
        node.stop()
        keyboard.restore()
        try:
            print()  # end the status line
        except OSError:
            pass
