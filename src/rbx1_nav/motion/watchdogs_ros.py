"""The motion runner's watchdogs: no /clock or a stopped one, the master
gone or restarted, the robot stalled, the transform old."""
import collections
import threading
import time

import rospy
from nav_msgs.msg import Odometry

from rbx1_nav.common.master_ros import MasterWatch
from rbx1_nav.common.master_watch import gone_text, restarted_text
from rbx1_nav.common.node_ros import CLOCK_WAIT, wait_for_clock
from rbx1_nav.common.ros_time import no_clock_text
from rbx1_nav.common.aborted import CourseAborted
from rbx1_nav.motion.loop import StallCheck

WARN_PERIOD = 10.0  # s between warnings about an old transform or a stall


def require_clock(wait):
    """Under /use_sim_time, wait up to ``wait`` wall s more (after
    start_node's CLOCK_WAIT) for the first /clock; CourseAborted if none."""
    if not wait_for_clock(wait):
        if rospy.is_shutdown():
            raise rospy.ROSInterruptException('shutdown waiting for /clock')
        raise CourseAborted('giving up, the robot not moved: %s'
                            % no_clock_text(CLOCK_WAIT + wait))


class ClockWatchdog(object):
    """Under /use_sim_time, stop the robot and shut the node down when
    ROS time stands still for max(2 s, ``tf_timeout``) of wall time: with
    a dead clock rospy.Rate.sleep() blocks the control loop, and with it
    the stale-tf check, forever."""

    def __init__(self, name, tf_timeout, stop):
        self.name = name
        self.limit = max(2.0, tf_timeout)
        self.stop = stop

    def start(self):
        """Start the thread, unless off simulated time."""
        if rospy.get_param('/use_sim_time', False):
            threading.Thread(target=self._watch, name='clock_watchdog',
                             daemon=True).start()

    def _watch(self):
        last, since = rospy.get_rostime(), time.monotonic()
        while not rospy.is_shutdown():
            rospy.rostime.wallsleep(0.1)
            now = rospy.get_rostime()
            if now != last:
                last, since = now, time.monotonic()
            elif time.monotonic() - since > self.limit:
                self.stop()
                rospy.logerr('%s: /clock has not advanced for %.1f s of '
                             'wall time (simulator or clock node gone?); '
                             'stopped the robot', self.name, self.limit)
                rospy.signal_shutdown('simulated clock stopped')
                return


def watch_master(name):
    """Say once when the master is unreachable, back, or restarted
    (polled off the control loop's thread: common.master_ros). The course
    goes on: ROS 1's topic connections are peer to peer."""
    MasterWatch(name, on_gone=lambda uri, problem: rospy.logwarn(
        gone_text(name, uri, problem)),
        on_back=lambda uri: rospy.loginfo('%s: the ROS master at %s is '
                                          'back', name, uri),
        on_restarted=lambda uri: rospy.logwarn(restarted_text(name, uri))
    ).start()


class StallWarnings(object):
    """The velocities the robot measured (``odom``), for Course.stalls.
    ``clock`` may keep them for the tick that counts them (Ticks.arrived),
    so a tick reads the same velocities on every run."""

    TOPIC = 'odom'

    def __init__(self, name, clock):
        self.clock = clock
        self.stall_check = StallCheck(name, lambda text: rospy.logwarn_throttle(
            WARN_PERIOD, text))
        # Drained by the control loop: the course is touched in one thread.
        self.velocities = collections.deque(maxlen=1000)
        self.sub = rospy.Subscriber(self.TOPIC, Odometry, self._on_odom,
                                    queue_size=100, tcp_nodelay=True)

    def _on_odom(self, msg):
        twist = msg.twist.twist
        item = (msg.header.stamp, twist.linear.x, twist.angular.z)
        if not self.clock.arrived(self.topic, msg, item):
            self.velocities.append(item)

    @property
    def topic(self):
        return self.sub.resolved_name

    def heard(self):
        """True when something publishes the odometry velocities."""
        return self.sub.get_num_connections() != 0

    def check(self, course, start):
        """Feed the velocities heard (and those the clock kept for this
        tick) to ``course.stalls``; ``start`` is the course's first tick."""
        self.velocities.extend(self.clock.take(self.topic, key=lambda item: item[0]))
        self.stall_check.check(course, start, self._drain())

    def _drain(self):
        while self.velocities:
            yield self.velocities.popleft()


class TfAgeWarnings(object):
    """Warn (throttled) when the transform steered by is older than
    ``max_age`` s (~max_tf_age): the robot has moved on since."""

    def __init__(self, name, max_age):
        self.name = name
        self.max_age = max_age

    def check(self, age, predicts, odom_frame, base_frame):
        """``predicts``: the course adds the commands sent since."""
        if age > self.max_age:
            rospy.logwarn_throttle(
                WARN_PERIOD, '%s: tf %s -> %s is %.3f s old when used (limit '
                '~max_tf_age %.3f s): a slow link to the robot or a busy machine; '
                '%s' % (self.name, odom_frame, base_frame, age, self.max_age,
                        'precise mode adds the commands sent since' if predicts
                        else 'the course steers by where the robot was'))
