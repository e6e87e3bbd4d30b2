"""The courses of ROS By Example's motion nodes, with the book's defaults.

No rospy here. One :class:`BookCourse` per course node, in degrees where the book's node
takes degrees; CourseConfig and OutAndBack hold the out-and-back in radians, for tests.
"""
import math
from collections import namedtuple

from rbx1_nav.common import params
from rbx1_nav.motion.course.course import Course, legs_course, legs_params
from rbx1_nav.motion.course.precise import PRECISE_PARAMS, approach

__all__ = ['BookCourse', 'OUT_AND_BACK', 'NAV_SQUARE', 'TIMED_OUT_AND_BACK',
           'CourseConfig', 'OutAndBack', 'expected_end_pose', 'COURSE_PARAMS']

BookCourse = namedtuple('BookCourse', 'params rate build')
BookCourse.__doc__ = """One of the book's course nodes: its course's params (the runner's come on
top), the book's control rate (Hz) and build(values), its Course from the values read."""


def _out_and_back_params(tolerance_unit):
    """The out-and-back's parameters, ``angular_tolerance`` in 'deg' (the node's) or 'rad'."""
    tolerance = math.radians(1.0) if tolerance_unit == 'rad' else 1.0  # 1 deg
    return legs_params(
        linear_speed=0.15, goal_distance=1.0, angular_speed=0.5, goal_angle=math.pi,
        angular_tolerance=tolerance, tolerance_unit=tolerance_unit, legs=2, pause=1.0
    ) + PRECISE_PARAMS


# The out-and-back's settings with the book's values; angular_tolerance in radians.
COURSE_PARAMS = _out_and_back_params('rad')


class CourseConfig(object):
    """The out-and-back's settings (angles in radians), the book's values as defaults."""

    def __init__(self, **settings):
        for spec in COURSE_PARAMS:
            setattr(self, spec.name, settings.pop(spec.name, spec.default))
        if settings:
            raise TypeError('unknown course settings: %s' % ', '.join(sorted(settings)))

    def _checked(self):
        return params.read_all(COURSE_PARAMS, lambda name, default: getattr(self, name))

    def problems(self):
        """A list of human-readable reasons the settings are unusable."""
        return self._checked()[1]

    def validate(self):
        """Store every setting in its type; raise ValueError naming every problem."""
        values, found = self._checked()
        if found:
            raise ValueError('; '.join(found))
        self.__dict__.update(values)
        return self


def course_steps(config):
    """The steps of the course a validated ``config`` describes."""
    return legs_course(config.goal_distance, config.goal_angle, config.legs, config.linear_speed,
                       config.angular_speed, config.angular_tolerance, config.pause,
                       approach(vars(config)))


def expected_end_pose(start, config):
    """Where a perfect robot would end the course begun at ``start``."""
    return Course(course_steps(config)).ideal_end(start)


class OutAndBack(Course):
    """The out-and-back Course, with its checked ``config`` and ``leg``."""

    def __init__(self, config=None):
        self.config = (config or CourseConfig()).validate()
        Course.__init__(self, course_steps(self.config))

    @property
    def leg(self):
        """The leg under way (the last one once done)."""
        return min(self.index // 4, self.config.legs - 1) + 1


def _out_and_back(values):
    """The out-and-back of the node's values (angular_tolerance in degrees)."""
    settings = {spec.name: values[spec.name] for spec in COURSE_PARAMS}
    settings['angular_tolerance'] = math.radians(values['angular_tolerance'])
    return OutAndBack(CourseConfig(**settings))


OUT_AND_BACK = BookCourse(_out_and_back_params('deg'), 20.0, _out_and_back)

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
