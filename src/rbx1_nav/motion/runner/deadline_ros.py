"""A start-up wait's limit in wall seconds. Start-up waits (~tf_wait: the transform, a cmd_vel
subscriber) wait for other processes, not the robot: no launch need scale them with sim_speed
(leaving scaled values for a later rosrun), and sim time may not move till the course joins."""
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
