"""Odometry calibration as in ROS By Example: the tests and the arithmetic.

No rospy here. A linear test drives ``test_distance`` on odometry, an
angular one turns ``test_angle``; after the robot has settled, the distance
or angle that odometry reports is compared with the one measured on the
floor (a tape measure, a protractor, or a simulator's ground truth), and

    scale correction = measured / odometry

is what the robot's driver must multiply its odometry by: a TurtleBot
driver's ``odom_linear_scale_correction`` / ``odom_angular_scale_correction``
(multiplied into the value it has now). The node-side
``odom_*_scale_correction`` field of the book's configs scales what this
node reads, so a candidate correction can be tried before it goes on the
driver: the test then drives until corrected odometry reaches the goal.
"""
import math
from collections import namedtuple

from rbx1_nav.motion import Course, Drive, Pause, Turn
from rbx1_nav.transform_utils import normalize_angle

__all__ = ['Kind', 'LINEAR', 'ANGULAR', 'PoseTrack', 'course', 'measure',
           'correction', 'report']

Kind = namedtuple('Kind', 'name goal measured correction unit speed_unit '
                         'quantity unit_name moved')
Kind.__doc__ = """One kind of calibration test: the names of its config
fields (goal, measured, correction), the units users give goals, tolerances
and speeds in, the quantity measured, the unit's name and the verb of the
motion."""

LINEAR = Kind('linear', 'test_distance', 'measured_distance',
              'odom_linear_scale_correction', 'm', 'm/s', 'distance', 'metres',
              'travelled')
ANGULAR = Kind('angular', 'test_angle', 'measured_angle',
               'odom_angular_scale_correction', 'deg', 'rad/s', 'angle',
               'degrees', 'turned')

# A measurement this far from odometry is a wrong unit or a typo, not a
# calibration (the config fields allow corrections of 0.5 to 2).
MAX_RATIO = 2.0


def course(kind, config, settle):
    """The test as a Course: the move, then ``settle`` s of stop.

    ``config`` maps the config fields (a dynamic_reconfigure config or a
    dict): goal and tolerance in the kind's unit, speed in m/s or rad/s.
    """
    scale = float(config[kind.correction])
    if kind is LINEAR:
        move = Drive(config['test_distance'] / scale, config['speed'],
                     config['tolerance'], label='linear test')
    else:
        move = Turn(math.radians(config['test_angle']) / scale,
                    config['speed'], math.radians(config['tolerance']),
                    label='angular test')
    return Course([move, Pause(settle)])


def measure(kind, start, end, turned):
    """What ``kind`` measures between two poses, in its unit (m or deg).

    Linear: the straight-line distance; angular: ``turned`` (rad, the
    unwrapped yaw change, which for a full turn is 2 pi, not 0).
    """
    if kind is LINEAR:
        return math.hypot(end.x - start.x, end.y - start.y)
    return math.degrees(turned)


class PoseTrack(object):
    """Distance and unwrapped turn of a stream of poses since the first.

    Fed every pose of a test (odometry or ground truth), it reports the
    straight-line distance from the first pose and the total yaw turned,
    which for a full turn is 2 pi, not 0.
    """

    def __init__(self):
        self.first = None
        self.last = None
        self.turned = 0.0

    def add(self, pose):
        if self.first is None:
            self.first = pose
        else:
            self.turned += normalize_angle(pose.yaw - self.last.yaw)
        self.last = pose

    def value(self, kind):
        """What ``kind`` measures from the first pose to the last."""
        return measure(kind, self.first, self.last, self.turned)


def correction(kind, odometry, measured):
    """measured / odometry, checked; ValueError with the reason if unusable."""
    for name, value in (('odometry', odometry), ('measured', measured)):
        if not (isinstance(value, (int, float)) and math.isfinite(value)
                and value > 0.0):
            raise ValueError('the %s %s must be a positive number, got %r'
                             % (name, kind.quantity, value))
    ratio = measured / odometry
    if not 1.0 / MAX_RATIO <= ratio <= MAX_RATIO:
        raise ValueError(
            'the measured %s (%g %s) differs from odometry (%g %s) by more '
            'than a factor %g: a wrong unit (%s) or a typo?' % (
                kind.quantity, measured, kind.unit, odometry, kind.unit,
                MAX_RATIO, kind.unit_name))
    return ratio


def report(kind, odometry, measured, source, node_factor=1.0):
    """The lines that tell the user what to set, arithmetic shown.

    ``odometry`` is what the driver reported; ``node_factor`` the node's own
    correction field, which the test applied on top (a candidate factor
    being tried). The result is relative to the driver's current setting.
    """
    seen = odometry * node_factor
    factor = correction(kind, seen, measured)
    lines = ['%s test: odometry %.4f %s%s, measured %.4f %s (%s)' % (
        kind.name, odometry, kind.unit,
        '' if node_factor == 1.0 else ' x this node\'s %s %.4f = %.4f %s' % (
            kind.correction, node_factor, seen, kind.unit),
        measured, kind.unit, source)]
    lines.append('%s = measured / odometry = %.4f / %.4f = %.4f' % (
        kind.correction, measured, seen, factor))
    total = factor * node_factor
    lines.append("Set the driver's %s to its current value x %.4f%s (a driver "
                 "at 1.0: %.4f); rerun the test to check." % (
                     kind.correction, total, '' if node_factor == 1.0 else
                     " (this node's %.4f x %.4f)" % (node_factor, factor),
                     total))
    return lines
