"""The motion runner's watchdogs: each one thing that can go wrong while
a course runs, noticed and said (and, where it must, the robot stopped).

* :func:`require_clock` and :class:`ClockWatchdog`: under /use_sim_time,
  the first /clock, and /clock stopping (unless the course's clock
  watches it itself: rbx1_nav.motion.ticks_ros);
* :func:`watch_master`: the ROS master gone, back, or restarted;
* :class:`StallWarnings`: the robot's odometry velocities, fed to the
  course's stall count (rbx1_nav.motion.loop.StallCheck);
* :class:`TfAgeWarnings`: the transform steered by older than ~max_tf_age;
"""
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
    """Under /use_sim_time, wait up to ``wait`` wall s more for the first
    /clock (start_node has waited CLOCK_WAIT s, and said so); CourseAborted
    when it does not come."""
    if not wait_for_clock(wait):
        if rospy.is_shutdown():
            raise rospy.ROSInterruptException('shutdown waiting for /clock')
        raise CourseAborted('giving up, the robot not moved: %s'
                            % no_clock_text(CLOCK_WAIT + wait))


class ClockWatchdog(object):
    """Under /use_sim_time, shut the node down if /clock stops.

    rospy.Rate.sleep() waits for simulated time, so with a dead clock the
    control loop, and with it the stale-tf check, would block forever.
    This thread measures wall time (the one place the node does) and shuts
    the node down, robot stopped (``stop()``), when ROS time stands still
    for max(2 s, ``tf_timeout``) of wall time.
    """

    def __init__(self, name, tf_timeout, stop):
        self.name = name
        self.limit = max(2.0, tf_timeout)
        self.stop = stop

    def start(self):
        """Start the thread, unless off simulated time."""
        if not rospy.get_param('/use_sim_time', False):
            return
        threading.Thread(target=self._watch, name='clock_watchdog',
                         daemon=True).start()

    def _watch(self):
        limit = self.limit
        last, since = rospy.get_rostime(), time.monotonic()
        while not rospy.is_shutdown():
            rospy.rostime.wallsleep(0.1)
            now = rospy.get_rostime()
            if now != last:
                last, since = now, time.monotonic()
            elif time.monotonic() - since > limit:
                self.stop()
                rospy.logerr('%s: /clock has not advanced for %.1f s of '
                             'wall time (simulator or clock node gone?); '
                             'stopped the robot', self.name, limit)
                rospy.signal_shutdown('simulated clock stopped')
                return


def watch_master(name):
    """Say once when the master becomes unreachable, when it is back,
    and when it restarted (rbx1_nav.common.master_ros: polled from a thread of
    its own with a timeout, so no master call can block the control
    loop; gone only after a few failed polls in a row, so a lossy link
    does not make the warning come and go). ROS 1's topic connections
    are peer to peer and outlive the master, so the course goes on."""
    MasterWatch(name, on_gone=lambda uri, problem: rospy.logwarn(
        gone_text(name, uri, problem)),
        on_back=lambda uri: rospy.loginfo('%s: the ROS master at %s is '
                                          'back', name, uri),
        on_restarted=lambda uri: rospy.logwarn(restarted_text(name, uri))
    ).start()


class StallWarnings(object):
    """The velocities the robot measured (``odom``), for Course.stalls;
    ``name`` is the node's, for the warnings; ``clock`` the course's,
    which may keep them for the tick that counts them
    (rbx1_nav.motion.ticks_ros.Ticks.arrived), so a tick reads the same
    velocities on every run (precise mode waits on them for a still
    robot)."""

    TOPIC = 'odom'

    def __init__(self, name, clock):
        self.clock = clock
        self.stall_check = StallCheck(name, lambda text: rospy.logwarn_throttle(
            WARN_PERIOD, text))
        # Drained by the control loop, so the course is only touched in
        # one thread.
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
        """Feed the robot's measured velocities (and those the clock kept
        for this tick, in stamp order) to ``course.stalls``, their stamps
        in seconds from ``start`` (the course's first tick, as the course
        counts time)."""
        self.velocities.extend(self.clock.take(self.topic, key=lambda item: item[0]))
        self.stall_check.check(course, start, self._drain())

    def _drain(self):
        while self.velocities:
            yield self.velocities.popleft()


class TfAgeWarnings(object):
    """Warn (at most every WARN_PERIOD s) when the transform steered by is
    older than ``max_age`` s (~max_tf_age): the robot has moved on since."""

    def __init__(self, name, max_age):
        self.name = name
        self.max_age = max_age

    def check(self, age, predicts, odom_frame, base_frame):
        """The transform ``odom_frame -> base_frame`` steered by is ``age`` s
        old; ``predicts``: the course adds the commands sent since."""
        limit = self.max_age
        if age > limit:
            rospy.logwarn_throttle(
                WARN_PERIOD, '%s: tf %s -> %s is %.3f s old when used (limit '
                '~max_tf_age %.3f s): a slow link to the robot or a busy machine; '
                '%s' % (self.name, odom_frame, base_frame, age, limit,
                        'precise mode adds the commands sent since' if predicts
                        else 'the course steers by where the robot was'))
