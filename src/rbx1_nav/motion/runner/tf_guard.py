"""Is the transform a course steers by one robot's? Not when two nodes publish it (two robots
with the same frames on one ``/tf``: tf hands the course whichever came last), nor when it jumps
further than the robot could move at the course's speeds (two robots, or a restarted driver).
Nor is it usable once it comes invalid (NaN: tf drops it, and the robot's pose is lost).

A jump between updates ``dt`` s apart may reach ``(MARGIN x top speed + EXTRA) x dt + SLACK``,
distance and heading alike; EXTRA and SLACK exceed a robot's noise, a filter's correction or an
overshooting motor controller. No rospy: times are float seconds, angles radians.
"""
import math

from rbx1_nav.motion.course.command import DRIVE
from rbx1_nav.motion.runner.invalid_poses import invalid_update_text

__all__ = ['MARGIN', 'EXTRA_LINEAR', 'EXTRA_ANGULAR', 'SLACK_LINEAR',
           'SLACK_ANGULAR', 'TransformGuard', 'top_speeds']

MARGIN = 2.0           # times the course's top speed
EXTRA_LINEAR = 0.5     # m/s on top
EXTRA_ANGULAR = 1.0    # rad/s on top
SLACK_LINEAR = 0.05    # m per update
SLACK_ANGULAR = 0.1    # rad per update

#: See docs/sim_time.md, "Several robots on one master".
FIX = ('give each robot its own frames (e.g. _odom_frame:=robot1/odom '
       '_base_frame:=robot1/base_footprint for the course, and its robot publishing those) or its '
       'own tf topic (/tf:=tf /tf_static:=tf_static for every node in the robot\'s namespace)')


def top_speeds(course):
    """(m/s, rad/s): the fastest a course's steps drive and turn (heading corrections turn too)."""
    linear = angular = 0.0
    for step in course.steps:
        axis = getattr(step, 'axis', None)
        if axis is None:
            continue
        if axis.kind == DRIVE:
            linear = max(linear, step.speed)
            angular = max(angular, getattr(step, 'heading_rate', None) or 0.0)
        else:
            angular = max(angular, step.speed)
    return linear, angular


class TransformGuard(object):
    """Watches ``parent -> child`` for a second publisher, for jumps (``linear`` m/s,
    ``angular`` rad/s: the course's top speeds) and for invalid updates; ``problem``: the first
    (a log line) or None."""

    def __init__(self, parent, child, linear, angular):
        self.parent, self.child = parent, child
        self.max_linear = MARGIN * linear + EXTRA_LINEAR
        self.max_angular = MARGIN * angular + EXTRA_ANGULAR
        self.sender = None  # the first node heard publishing it
        self.last = None    # (stamp, x, y, yaw) of its last update
        self.problem = None

    def invalid(self, sender, problem):
        """An invalid update (``problem``: invalid_poses.pose_problem's) from node ``sender``;
        returns ``problem``."""
        if self.problem is None:
            self.problem = invalid_update_text(self.parent, self.child, sender, problem)
        return self.problem

    def heard(self, sender, stamp, x, y, yaw):
        """An update from node ``sender``, stamped ``stamp`` s; returns ``problem``."""
        if self.problem is not None:
            return self.problem
        where = 'tf %s -> %s' % (self.parent, self.child)
        if self.sender is None:
            self.sender = sender
        elif sender != self.sender:
            self.problem = ('%s comes from two nodes, %s and %s: two robots with the same '
                            'frames on one tf (the course would steer by both). Stopped the '
                            'robot. Fix: %s' % (where, self.sender, sender, FIX))
            return self.problem
        last, self.last = self.last, (stamp, x, y, yaw)
        if last is None or stamp < last[0]:  # first, or time moved back
            return None
        dt = stamp - last[0]
        moved = math.hypot(x - last[1], y - last[2])
        turned = abs(math.remainder(yaw - last[3], 2 * math.pi))
        linear_limit = self.max_linear * dt + SLACK_LINEAR
        angular_limit = self.max_angular * dt + SLACK_ANGULAR
        if moved > linear_limit:
            jump = '%.3f m in %.2f s (limit %.3f m)' % (moved, dt, linear_limit)
        elif turned > angular_limit:
            jump = '%.1f deg in %.2f s (limit %.1f deg)' % (
                math.degrees(turned), dt, math.degrees(angular_limit))
        else:
            return None
        self.problem = (
            '%s moved %s, faster than the robot can at this course\'s speeds (%g x its top speeds '
            '+ %g m/s, %g rad/s): two robots with the same frames on one tf, or the robot\'s '
            'odometry reset (a restarted driver)? Stopped the robot. Fix: %s' % (
                where, jump, MARGIN, EXTRA_LINEAR, EXTRA_ANGULAR, FIX))
        return self.problem
