"""The parameters of a course of legs (course.legs_course), as the book's nodes declare them."""
import math

from rbx1_nav.common import params
from rbx1_nav.common.params import param
from rbx1_nav.motion.course.command import (MAX_ANGLE, MAX_ANGULAR_SPEED, MAX_DISTANCE,
                                            MAX_LINEAR_SPEED, MAX_TOLERANCE)

__all__ = ['legs_params']

#: Where the book's course nodes differ in goal_angle's unit, as they do.
ANGLE_NOTES = {
    'rad': "as in the book's odom_out_and_back.py and timed_out_and_back.py; "
           "nav_square.py takes degrees",
    'deg': "as in the book's nav_square.py; odom_out_and_back.py and "
           "timed_out_and_back.py take radians",
}


def legs_params(linear_speed, goal_distance, angular_speed, goal_angle, angle_unit='rad',
                angular_tolerance=None, tolerance_unit='deg', legs=None, pause=1.0):
    """The parameters of a :func:`legs_course`, with these defaults, angles
    in 'rad' or 'deg'; a tolerance or leg count of None is no parameter."""
    def in_unit(angle, unit):
        return math.degrees(angle) if unit == 'deg' else angle

    max_angle = in_unit(MAX_ANGLE, angle_unit)
    specs = [
        param('linear_speed', linear_speed, params.number, 'm/s',
              'forward speed', maximum=MAX_LINEAR_SPEED, **params.POSITIVE),
        param('goal_distance', goal_distance, params.number, 'm',
              'length of each leg (negative: backwards)',
              minimum=-MAX_DISTANCE, maximum=MAX_DISTANCE),
        param('angular_speed', angular_speed, params.number, 'rad/s',
              'turn rate', maximum=MAX_ANGULAR_SPEED, **params.POSITIVE),
        param('goal_angle', goal_angle, params.number, angle_unit,
              'turn after each leg (negative: clockwise)', note=ANGLE_NOTES[angle_unit],
              minimum=-max_angle, maximum=max_angle),
    ]
    if angular_tolerance is not None:
        specs.append(param('angular_tolerance', angular_tolerance, params.number, tolerance_unit,
                           'a turn stops this much short', minimum=0.0,
                           maximum=in_unit(MAX_TOLERANCE, tolerance_unit)))
    if legs is not None:
        specs.append(param('legs', legs, params.integer, '', 'number of legs',
                           minimum=1, maximum=1000))
    specs.append(param('pause', pause, params.number, 's',
                       'stop after each drive and turn', minimum=0.0))
    return tuple(specs)
