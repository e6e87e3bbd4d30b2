"""A start-up wait's limit in wall seconds. The runner's start-up waits
(~tf_wait: the transform, a cmd_vel subscriber) wait for other processes,
not the robot, so a launch file need not scale them with its sim_speed
(leaving scaled values on the master for a later rosrun); and simulated
time may not move before the course takes part in it."""
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
