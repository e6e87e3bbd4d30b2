"""A signal that arrives while teleop_keyboard is publishing a motion.

The node's stop is a shutdown hook. It once ran inside the signal handler,
in the main thread, in the middle of the publish the signal interrupted: the
zero Twist went out first and the interrupted motion after it, the robot's
last command (teleop_keyboard.test saw it once in many runs, after a closed
terminal). Here the signal comes at that moment every time: a stand-in
publisher sends it to its own process while it is publishing a motion.
No master is needed: nothing here goes over the network.
"""
import subprocess
import sys

import pytest

SCRIPT = r'''
import os, signal, sys, time
import rospy
from rbx1_nav.motion.teleop import teleop_ros

sent = []

class Publisher(object):
    """Records each Twist; sends ``SIGNAL`` to this process during a motion."""
    resolved_name = 'cmd_vel'

    def __init__(self, *args, **kwargs):
        pass

    def publish(self, twist):
        if twist.linear.x and not sent:
            os.kill(os.getpid(), SIGNAL)
            time.sleep(0.2)  # a handler in this thread runs before this ends
        sent.append(twist.linear.x)

SIGNAL = getattr(signal, sys.argv[1])
teleop_ros.rospy.Publisher = Publisher
teleop_ros.shut_down_on_signals((signal.SIGINT, signal.SIGTERM, signal.SIGHUP))
node = teleop_ros.TeleopKeyboard(dict(
    linear_speed=0.3, angular_speed=1.0, max_linear_speed=1.0,
    max_angular_speed=3.0, key_timeout=0.6, rate=10.0))
node.publish((-0.3, 0.0))
deadline = time.monotonic() + 10.0
while not rospy.is_shutdown() and time.monotonic() < deadline:
    time.sleep(0.01)
time.sleep(0.2)  # the shutdown thread's last publishes, if any
node.publish((-0.3, 0.0))  # the main loop's next command: must not go out
print('SENT %r SHUTDOWN %s' % (sent, rospy.is_shutdown()))
'''


@pytest.mark.parametrize('signame', ['SIGHUP', 'SIGINT', 'SIGTERM'])
def test_a_signal_during_a_publish_leaves_the_stop_last(signame):
    done = subprocess.run([sys.executable, '-c', SCRIPT, signame],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          universal_newlines=True, timeout=60)
    assert done.returncode == 0, done.stdout
    assert 'SENT [-0.3, 0.0] SHUTDOWN True' in done.stdout, done.stdout
