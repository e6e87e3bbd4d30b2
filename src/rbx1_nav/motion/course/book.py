"""The courses of ROS By Example's motion nodes, with the book's defaults.

No rospy here. One :class:`BookCourse` per course node, in degrees where the book's node
takes degrees. A node reads and checks its parameters once (common.node_ros.start_node) and
builds its course from them; :meth:`BookCourse.course` does the same from keyword settings.
"""
import math
from collections import namedtuple

from rbx1_nav.common import params
from rbx1_nav.motion.course.course import Course, legs_course
from rbx1_nav.motion.course.legs_params import legs_params
from rbx1_nav.motion.course.precise import PRECISE_PARAMS, approach

__all__ = ['BookCourse', 'OUT_AND_BACK', 'NAV_SQUARE', 'TIMED_OUT_AND_BACK']


class BookCourse(namedtuple('BookCourse', 'params rate build')):
    """One of the book's course nodes: its course's params (the runner's come on top), the
    book's control rate (Hz) and build(values), its Course from the values read."""

    def values(self, **settings):
        """``settings`` over the defaults, checked as the node checks its parameters;
        ValueError naming every problem."""
        unknown = set(settings) - {spec.name for spec in self.params}
        if unknown:
            raise TypeError('unknown course settings: %s' % ', '.join(sorted(unknown)))
        values, problems = params.read_all(self.params, settings.get)
        if problems:
            raise ValueError('; '.join(problems))
        return values

    def course(self, **settings):
        """The Course of ``settings`` (the node's names and units) over the defaults."""
        return self.build(self.values(**settings))


def _out_and_back(values):
    """The out-and-back of the node's values (angular_tolerance in degrees)."""
    return Course(legs_course(
        values['goal_distance'], values['goal_angle'], values['legs'], values['linear_speed'],
        values['angular_speed'], math.radians(values['angular_tolerance']), values['pause'],
        approach(values)))


OUT_AND_BACK = BookCourse(
    legs_params(linear_speed=0.15, goal_distance=1.0, angular_speed=0.5, goal_angle=math.pi,
                angular_tolerance=1.0, legs=2, pause=1.0) + PRECISE_PARAMS,
    20.0, _out_and_back)

SIDES = 4  # nav_square's legs


def _nav_square(values):
    """The square of the node's values (angles in degrees)."""
    return Course(legs_course(
        values['goal_distance'], math.radians(values['goal_angle']), SIDES, values['linear_speed'],
        values['angular_speed'], math.radians(values['angular_tolerance']), values['pause'],
        approach(values)))


NAV_SQUARE = BookCourse(
    legs_params(linear_speed=0.2, goal_distance=1.0, angular_speed=0.7, goal_angle=90.0,
                angle_unit='deg', angular_tolerance=2.0, pause=1.0) + PRECISE_PARAMS,
    20.0, _nav_square)


def _timed_out_and_back(values):
    """The out-and-back open loop on time, one control period (1 / rate) a cycle."""
    return Course(legs_course(values['goal_distance'], values['goal_angle'], values['legs'],
                              values['linear_speed'], values['angular_speed'],
                              pause=values['pause'], period=1.0 / values['rate']))


TIMED_OUT_AND_BACK = BookCourse(
    legs_params(linear_speed=0.2, goal_distance=1.0, angular_speed=1.0,
                goal_angle=math.pi, legs=2, pause=1.0),
    50.0, _timed_out_and_back)
