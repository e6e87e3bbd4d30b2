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

from rbx1_nav.motion.course.course import Course
from rbx1_nav.motion.course.steps import Drive, Pause, Turn
from rbx1_nav.transform_utils import normalize_angle

__all__ = ['Kind', 'LINEAR', 'ANGULAR', 'PoseTrack', 'course', 'measure',
           'correction', 'report', 'far_from_one', 'measured_refusal',
           'Answers', 'USUAL', 'MAX_RATIO']

Kind = namedtuple('Kind', 'name goal measured correction unit speed_unit '
                         'quantity unit_name moved causes')
Kind.__doc__ = """One kind of calibration test: the names of its config
fields (goal, measured, correction), the units users give goals, tolerances
and speeds in, the quantity measured, the unit's name, the verb of the
motion, and the usual causes of a factor far from 1."""

LINEAR = Kind('linear', 'test_distance', 'measured_distance',
              'odom_linear_scale_correction', 'm', 'm/s', 'distance', 'metres',
              'travelled', "a wrong wheel radius or encoder ticks per "
              "revolution in the driver's parameters, tracks or wheels that "
              "slip, or a measurement in the wrong unit (give metres)")
ANGULAR = Kind('angular', 'test_angle', 'measured_angle',
               'odom_angular_scale_correction', 'deg', 'rad/s', 'angle',
               'degrees', 'turned', "a skid-steer or tracked base (its wheels "
               "slide sideways in a turn: factors of 0.3 to 0.5 are normal), "
               "a wrong wheel base (wheel separation) in the driver's "
               "parameters, or a measurement in the wrong unit (give degrees)")

# Factors a calibrated differential drive usually needs; outside them the
# factor is still used, with a warning naming the usual causes.
USUAL = (0.8, 1.25)
# A measured / odometry ratio beyond 1 / MAX_RATIO .. MAX_RATIO says one of
# them saw no motion (the robot's driver accepts factors up to 100 too).
MAX_RATIO = 100.0


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
    """measured / odometry, checked; ValueError with the reason if unusable.

    Any physically possible factor is accepted: refused are only a
    measurement or odometry that is zero, negative, NaN or infinite, and
    a ratio beyond 1 / MAX_RATIO .. MAX_RATIO, which says the robot did not
    move (or its odometry saw no motion). :func:`far_from_one` tells
    whether a factor is unusual.
    """
    for name, value in (('odometry', odometry), ('measured', measured)):
        if not (isinstance(value, (int, float)) and math.isfinite(value)
                and value > 0.0):
            raise ValueError('the %s %s must be a positive number, got %r'
                             % (name, kind.quantity, value))
    ratio = measured / odometry
    if ratio < 1.0 / MAX_RATIO:
        raise ValueError(
            'the measured %s (%g %s) is under 1/%g of what odometry reports '
            '(%g %s): the robot did not move (wheels off the ground?), or the '
            'measurement is wrong' % (kind.quantity, measured, kind.unit,
                                      MAX_RATIO, odometry, kind.unit))
    if ratio > MAX_RATIO:
        raise ValueError(
            'odometry reports %g %s, under 1/%g of the measured %s (%g %s): '
            'odometry did not see the robot move (encoders not counting?), '
            'or the measurement is wrong' % (odometry, kind.unit, MAX_RATIO,
                                             kind.quantity, measured, kind.unit))
    return ratio


def measured_refusal(kind, value, node):
    """None for a usable ``measured_*`` value (a positive finite number);
    otherwise the warning that refuses it, naming the value, why, and the
    command to give it again (``node``: the calibration node's name).
    0 means "not measured yet" and is never passed here."""
    if (isinstance(value, (int, float)) and not isinstance(value, bool)
            and math.isfinite(value) and value > 0.0):
        return None
    example = '0.97' if kind is LINEAR else '352'
    return ('%s %r refused: the %s the robot really %s must be a positive '
            'number of %s (0 means not measured yet); nothing computed, the '
            'field is back at 0. Give the measurement: rosrun '
            'dynamic_reconfigure dynparam set %s %s %s'
            % (kind.measured, value, kind.quantity, kind.moved, kind.unit_name,
               node, kind.measured, example))


class Answers(object):
    """The ``measured_*`` values given through reconfigure, each used once
    and none lost, whenever it is typed.

    :meth:`reconfigured` sees every configuration the server is given (a
    dict, changed in place: the server keeps what it returns). A refused
    value is refused at once, the field set back to 0. A test's start sets
    the field back to 0, so that a value typed while the test runs is a
    change (the last test's number typed again too), and a value typed
    then is kept until the node takes it (:meth:`take`) after the test has
    ended: it is used as if typed after "odometry says". The field keeps
    it, as it keeps a value typed after the end.
    """

    def __init__(self, kind, node):
        self.kind = kind
        self.node = node  # the node's name, for the lines to type
        self.field = 0.0  # the measured field as last seen
        self.new = 0.0  # a usable value given and not yet taken, or 0
        self.testing = False  # start_test as last seen

    def reconfigured(self, config):
        """Note ``config``; return (level, line) to tell the user at once
        ('warn': a refused value; 'info': one kept for the test's end), or
        None."""
        kind = self.kind
        value = config[kind.measured]
        note = None
        if value != self.field:  # the field never keeps a NaN: refused
            self.field = value
            refusal = value != 0.0 and measured_refusal(kind, value, self.node)
            if refusal:
                config[kind.measured] = self.field = 0.0
                note = ('warn', refusal)
            else:  # 0 takes back a value not used yet
                self.new = value
                if value and self.testing and config['start_test']:
                    note = ('info', '%s %g kept: the test is still running; it is '
                            'used when the test ends, as if given after "odometry '
                            'says"' % (kind.measured, value))
        if config['start_test'] and not self.testing:
            config[kind.measured] = self.field = 0.0
        self.testing = bool(config['start_test'])
        return note

    def take(self):
        """The newest usable value given and not yet taken, or 0."""
        value, self.new = self.new, 0.0
        return value


def far_from_one(kind, factor):
    """A warning for a factor outside :data:`USUAL`, naming the usual
    causes; None for a usual one."""
    if USUAL[0] <= factor <= USUAL[1]:
        return None
    return ('%s %.4f is far from 1 (outside %g..%g). Usual causes: %s. The '
            'factor is still right for this robot if the measurement is '
            % (kind.correction, factor, USUAL[0], USUAL[1], kind.causes)
            + 'right; check those causes first.')


def report(kind, odometry, measured, source, node_factor=1.0):
    """(lines, warning): the lines that tell the user what to set,
    arithmetic shown, and :func:`far_from_one`'s warning or None.

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
    return lines, far_from_one(kind, total)
