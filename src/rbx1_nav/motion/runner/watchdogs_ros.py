"""The runner's watchdogs: master gone or restarted, robot stalled, old tf (/clock's: sim_time)."""
import collections
import math

import rospy
from nav_msgs.msg import Odometry

from rbx1_nav.common.master_ros import MasterWatch
from rbx1_nav.common.master_watch import gone_text, restarted_text
from rbx1_nav.common.rospy_private_ros import sender
from rbx1_nav.motion.runner.invalid_poses import InvalidPoses, invalid_odom_text, pose_problem
from rbx1_nav.motion.runner.loop import StallCheck

WARN_PERIOD = 10.0  # s between warnings about an old transform or a stall


def watch_master(name):
    """Say once when the master is unreachable, back or restarted (polled off the control loop's
    thread); the course goes on: ROS 1's topic connections are peer to peer."""
    MasterWatch(name, on_gone=lambda uri, problem: rospy.logwarn(gone_text(name, uri, problem)),
                on_back=lambda uri: rospy.loginfo('%s: the ROS master at %s is back', name, uri),
                on_restarted=lambda uri: rospy.logwarn(restarted_text(name, uri))).start()


class OdomVelocities(object):
    """The velocities the robot measured (``odom``), for Course.stalls. ``link`` may keep them
    for the tick that counts them (RobotLink.arrived), so a tick reads the same ones on every run.
    An invalid message (NaN, a rotation not a unit quaternion) is named once per node that sends
    it; non-finite velocities are skipped."""

    TOPIC = 'odom'

    def __init__(self, name, link):
        self.name = name
        self.link = link
        self.invalid = InvalidPoses()
        self.stall_check = StallCheck(name, lambda text: rospy.logwarn_throttle(WARN_PERIOD, text))
        # Drained by the control loop: the course is touched in one thread.
        self.velocities = collections.deque(maxlen=1000)
        self.sub = rospy.Subscriber(self.TOPIC, Odometry, self._on_odom,
                                    queue_size=100, tcp_nodelay=True)

    def _on_odom(self, msg):
        twist = msg.twist.twist
        item = (msg.header.stamp, twist.linear.x, twist.angular.z)
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        problem = pose_problem((p.x, p.y, p.z), (q.x, q.y, q.z, q.w), item[1:])
        if problem is not None and self.invalid.heard(sender(msg), problem):
            rospy.logwarn('%s: %s', self.name, invalid_odom_text(self.topic, sender(msg), problem))
        if not self.link.arrived(self.topic, msg, item):
            self.velocities.append(item)

    @property
    def topic(self):
        return self.sub.resolved_name

    def heard(self):
        """True when something publishes the odometry velocities."""
        return self.sub.get_num_connections() != 0

    def check(self, course, start):
        """Feed ``course.stalls`` the velocities heard or kept for this tick; ``start``: tick 0."""
        self.velocities.extend(self.link.take(self.topic, key=lambda item: item[0]))
        self.stall_check.check(course, start, self._drain())

    def _drain(self):
        while self.velocities:
            item = self.velocities.popleft()
            if math.isfinite(item[1]) and math.isfinite(item[2]):
                yield item


class TfAgeWarnings(object):
    """Warn (throttled) when the tf steered by is over ``max_age`` s old: the robot moved on."""

    def __init__(self, name, max_age):
        self.name = name
        self.max_age = max_age

    def check(self, age, precise, odom_frame, base_frame):
        """``precise``: precise mode, which adds the commands sent since."""
        if age > self.max_age:
            rospy.logwarn_throttle(
                WARN_PERIOD, '%s: tf %s -> %s is %.3f s old when used (limit ~max_tf_age %.3f s): '
                'a slow link to the robot or a busy machine; %s' % (
                    self.name, odom_frame, base_frame, age, self.max_age,
                    'precise mode adds the commands sent since' if precise
                    else 'the course steers by where the robot was'))
