"""A tape measure for simulation: the simulator's ground_truth topic.

Calibration nodes compare what odometry says with what really happened; on
a real robot the user measures the floor, in simulation a
``~ground_truth_topic`` (nav_msgs/Odometry, e.g. fake_turtlebot's
``ground_truth``) stands in. :class:`GroundTruth` follows it.
"""
import threading

import rospy
from nav_msgs.msg import Odometry

from rbx1_nav import params
from rbx1_nav.calibration import PoseTrack
from rbx1_nav.params import param
from rbx1_nav.transform_utils import Pose2D, quat_to_angle

TRUTH_PARAM = param('ground_truth_topic', '', params.text, '',
                    "Odometry topic that stands in for the tape measure; "
                    "'' = measure by hand", allow_empty=True)


class GroundTruth(object):
    """The latest pose on ``topic`` and, between start() and stop(), a track."""

    def __init__(self, topic):
        self.topic = topic
        self.lock = threading.Lock()
        self.pose = None
        self.track = None
        rospy.Subscriber(topic, Odometry, self._on_pose, queue_size=100)

    def _on_pose(self, msg):
        p = msg.pose.pose
        pose = Pose2D(p.position.x, p.position.y, quat_to_angle(p.orientation))
        with self.lock:
            self.pose = pose
            if self.track is not None:
                self.track.add(pose)

    def latest(self):
        """The newest pose, or None if nothing came yet."""
        with self.lock:
            return self.pose

    def wait(self, timeout):
        """The newest pose, waiting up to ``timeout`` s (ROS time) for one."""
        deadline = rospy.Time.now() + rospy.Duration(timeout)
        poll = rospy.Rate(20)
        while self.latest() is None and rospy.Time.now() < deadline:
            poll.sleep()
        return self.latest()

    def start(self):
        """Begin a PoseTrack of every pose from now on."""
        with self.lock:
            self.track = PoseTrack()

    def stop(self):
        """End the track; return it (None if no pose arrived meanwhile)."""
        with self.lock:
            track, self.track = self.track, None
        return track if track is not None and track.first is not None else None
