"""Planar motion geometry, without rospy or numpy (sim.diff_drive.arc_steps: arrays)."""
import math

from rbx1_nav.transform_utils import Pose2D, normalize_angle

__all__ = ['arc_step']


def arc_step(pose, ds, dtheta):
    """The Pose2D after ``ds`` metres from ``pose`` turning ``dtheta`` rad, on the
    arc a differential drive traces at constant (v, w): exact, unlike Euler."""
    half = 0.5 * dtheta
    chord = ds if half == 0.0 else ds * math.sin(half) / half
    heading = pose.yaw + half
    return Pose2D(pose.x + chord * math.cos(heading), pose.y + chord * math.sin(heading),
                  normalize_angle(pose.yaw + dtheta))
