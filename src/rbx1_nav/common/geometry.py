"""Planar motion geometry shared by the controller and the simulators.

No rospy and no numpy here: the motion core predicts where the robot will
be with :func:`arc_step`; the simulators step many robots at once with its
array form, rbx1_nav.sim.diff_drive.arc_steps (a unit test holds the two
together).
"""
import math

from rbx1_nav.transform_utils import Pose2D, normalize_angle

__all__ = ['arc_step']


def arc_step(pose, ds, dtheta):
    """The Pose2D after travelling ``ds`` metres from ``pose`` while turning
    ``dtheta`` rad.

    The path is a circular arc (a straight line when ``dtheta`` is 0), which
    is what a differential drive traces at constant (v, w): exact, unlike
    forward Euler. The chord of the arc is ``ds * sin(dtheta/2)/(dtheta/2)``
    and points along the mean heading.
    """
    half = 0.5 * dtheta
    chord = ds if half == 0.0 else ds * math.sin(half) / half
    heading = pose.yaw + half
    return Pose2D(pose.x + chord * math.cos(heading),
                  pose.y + chord * math.sin(heading),
                  normalize_angle(pose.yaw + dtheta))
