"""A start-up wait's limit, for the motion runner's pieces.

The runner's start-up waits (the transform, a cmd_vel subscriber) wait
for other processes rather than for the robot: under lockstep they count
wall seconds, since simulated time only moves once the node is a member.
"""
import time

import rospy


class Deadline(object):
    """A wait's limit: in ROS time, or in wall time under lockstep."""

    def __init__(self, seconds, wall):
        self.wall = wall
        self.end = (time.monotonic() + seconds if wall
                    else rospy.Time.now() + rospy.Duration(seconds))

    def expired(self):
        return (time.monotonic() if self.wall else rospy.Time.now()) >= self.end

    def poll(self, hz):
        """Sleep one poll period (wall time under lockstep)."""
        if self.wall:
            rospy.rostime.wallsleep(1.0 / hz)
        else:
            rospy.sleep(1.0 / hz)
