"""A start-up wait's limit, for the motion runner's pieces.

The runner's start-up waits (the transform, a cmd_vel subscriber) wait
for other processes rather than for the robot, so they count wall
seconds: under simulated time, ROS time may not move until the course
itself takes part in it.
"""
import time

import rospy


class Deadline(object):
    """``seconds`` of wall time from now."""

    def __init__(self, seconds):
        self.end = time.monotonic() + seconds

    def expired(self):
        return time.monotonic() >= self.end

    @staticmethod
    def poll(hz):
        """Sleep one poll period (wall time)."""
        rospy.rostime.wallsleep(1.0 / hz)
