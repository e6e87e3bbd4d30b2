"""A tape measure for simulation: the simulator's ground_truth topic.

Calibration nodes compare what odometry says with what really happened; on
a real robot the user measures the floor, in simulation a
``~ground_truth_topic`` (nav_msgs/Odometry, e.g. fake_turtlebot's
``ground_truth``) stands in. :class:`GroundTruth` follows it.

A message can reach this node later than the tf it is compared with (a
loaded machine, simulated time at 25x), so every reading is by stamp: a
test starts at the first pose stamped at its start and ends at the first
pose stamped at its end, never at whatever arrived last.
"""
import threading
import time

import rospy
from nav_msgs.msg import Odometry

from rbx1_nav.common import params
from rbx1_nav.calibration.scale import PoseTrack
from rbx1_nav.common.params import param
from rbx1_nav.transform_utils import Pose2D, quat_to_angle

TRUTH_PARAM = param('ground_truth_topic', '', params.text, '',
                    "Odometry topic that stands in for the tape measure; "
                    "'' = measure by hand", allow_empty=True)


#: Wall seconds to wait for a pose stamped at a given time before taking
#: the newest one with a warning.
STAMP_WAIT = 5.0


class GroundTruth(object):
    """The latest pose on ``topic`` and, between start() and stop(), a track."""

    def __init__(self, topic):
        self.topic = topic
        self.lock = threading.Condition()
        self.pose = None
        self.stamp = None
        self.track = None
        self.track_from = None
        rospy.Subscriber(topic, Odometry, self._on_pose, queue_size=100)

    def _on_pose(self, msg):
        p = msg.pose.pose
        pose = Pose2D(p.position.x, p.position.y, quat_to_angle(p.orientation))
        stamp = msg.header.stamp
        if stamp.is_zero():  # an unstamped source: take it as it comes
            stamp = rospy.Time.now()
        with self.lock:
            self.pose, self.stamp = pose, stamp
            if self.track is not None and stamp >= self.track_from:
                self.track.add(pose)
            self.lock.notify_all()

    def latest(self):
        """The newest pose, or None if nothing came yet."""
        with self.lock:
            return self.pose

    def at(self, stamp):
        """The newest pose once one stamped at or after ``stamp`` came.

        Waits up to STAMP_WAIT s of wall time; then warns and returns the
        newest pose (None if none came at all)."""
        with self.lock:
            if not self.lock.wait_for(lambda: self._reached(stamp), STAMP_WAIT):
                rospy.logwarn('nothing on %s stamped at or after %.3f s within '
                              '%.0f s; using the newest pose (stamped %s)',
                              self.topic, stamp.to_sec(), STAMP_WAIT,
                              'never' if self.stamp is None
                              else '%.3f s' % self.stamp.to_sec())
            return self.pose

    def _reached(self, stamp):
        return (self.stamp is not None and self.stamp >= stamp) or \
            rospy.core.is_shutdown_requested()

    def wait(self, timeout):
        """The newest pose, waiting for one up to ``timeout`` s of ROS time
        and at least as long of wall time (a subscription connects in wall
        time, however fast simulated time runs: CI saw 5 s of simulated
        time pass in 0.5 s)."""
        deadline = rospy.Time.now() + rospy.Duration(timeout)
        wall_deadline = time.monotonic() + timeout
        with self.lock:
            while self.pose is None and not rospy.core.is_shutdown_requested():
                if (time.monotonic() >= wall_deadline
                        and rospy.Time.now() >= deadline):
                    break
                self.lock.wait(0.05)
            return self.pose

    def start(self, stamp):
        """Begin a PoseTrack of every pose stamped from ``stamp`` on."""
        with self.lock:
            self.track, self.track_from = PoseTrack(), stamp

    def stop(self, stamp):
        """End the track once a pose stamped at or after ``stamp`` came (see
        :meth:`at`); return it (None if no pose arrived meanwhile)."""
        self.at(stamp)
        with self.lock:
            track, self.track = self.track, None
        return track if track is not None and track.first is not None else None
