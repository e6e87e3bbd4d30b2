"""The odometry out-and-back course of ROS By Example, on the motion core.

No rospy here. The course is [drive ``goal_distance``, pause, turn
``goal_angle``, pause] x ``legs`` (:func:`rbx1_nav.motion.course.legs_course`);
the rules for drives, turns, the tolerance and precise mode are those of
:mod:`rbx1_nav.motion.steps` and :mod:`rbx1_nav.motion.precise`. The node ``nodes/odom_out_and_back.py`` reads the
same settings as private parameters (``~angular_tolerance`` in degrees, as in
the book; radians here) and runs the course through ``rbx1_nav.motion.runner_ros``.
"""
import math

from rbx1_nav.common import params
from rbx1_nav.motion.course import Course, legs_course, legs_params
from rbx1_nav.motion.precise import PRECISE_PARAMS, approach

__all__ = ['CourseConfig', 'OutAndBack', 'expected_end_pose', 'COURSE_PARAMS']

# The course's settings with the book's values; angular_tolerance in radians.
COURSE_PARAMS = legs_params(
    linear_speed=0.15, goal_distance=1.0, angular_speed=0.5,
    goal_angle=math.pi, angular_tolerance=math.radians(1.0),
    tolerance_unit='rad', legs=2,
    pause=1.0) + PRECISE_PARAMS


class CourseConfig(object):
    """The course's settings, with the book's values as defaults.

    Angles are in radians here. A negative ``goal_distance`` drives
    backwards, a negative ``goal_angle`` turns clockwise.
    """

    def __init__(self, **settings):
        for spec in COURSE_PARAMS:
            setattr(self, spec.name, settings.pop(spec.name, spec.default))
        if settings:
            raise TypeError('unknown course settings: %s'
                            % ', '.join(sorted(settings)))

    def _checked(self):
        return params.read_all(COURSE_PARAMS,
                               lambda name, default: getattr(self, name))

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
    values = vars(config)
    return legs_course(config.goal_distance, config.goal_angle, config.legs,
                       config.linear_speed, config.angular_speed,
                       config.angular_tolerance, config.pause, approach(values))


def expected_end_pose(start, config):
    """Where a perfect robot would end the course begun at ``start``."""
    return Course(course_steps(config)).ideal_end(start)


class OutAndBack(Course):
    """The out-and-back course as a :class:`rbx1_nav.motion.course.Course`.

    Adds ``config`` (the checked settings) and ``leg`` (1-based) to it.
    """

    def __init__(self, config=None):
        self.config = (config or CourseConfig()).validate()
        Course.__init__(self, course_steps(self.config))

    @property
    def leg(self):
        """The leg under way (the last one once done)."""
        return min(self.index // 4, self.config.legs - 1) + 1
