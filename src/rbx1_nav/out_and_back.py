"""The odometry out-and-back course of ROS By Example as a plain state machine.

No rospy here: the node ``nodes/odom_out_and_back.py`` reads the robot's pose
from tf, calls :meth:`OutAndBack.update` once per control cycle with that
pose and the current ROS time, and publishes the :class:`Command` it returns.
Tests drive the same class with a simulated robot and a fake clock.

The course, as in the book: for each leg, drive ``goal_distance`` straight
ahead (distance is the Euclidean distance from where the leg started), stop,
pause, turn in place through ``goal_angle``, stop, pause. The turn adds up
``normalize_angle`` of the change in yaw between successive readings, so it
works across the +-pi wrap and for turns of pi or more, and ends once
``turned + angular_tolerance >= goal_angle`` (measured in the turn's own
direction, so a clockwise turn stops equally early).

Precise mode slows down when nearing each distance and angle goal (speed
proportional to what remains, never below a creep speed), holds the leg's
starting heading while driving, and stops at the goal itself rather than
``angular_tolerance`` short of it, so the final error shrinks to about one
control step at creep speed.
"""
import math
from collections import namedtuple

from rbx1_nav import params
from rbx1_nav.transform_utils import Pose2D, normalize_angle

__all__ = ['Pose2D', 'Command', 'STOP', 'CourseConfig', 'OutAndBack',
           'expected_end_pose', 'pose_error']

Command = namedtuple('Command', 'linear angular')
Command.__doc__ = 'A velocity command: forward speed (m/s), turn rate (rad/s).'

STOP = Command(0.0, 0.0)

DRIVE, TURN, PAUSE, DONE = 'drive', 'turn', 'pause', 'done'


class CourseConfig(object):
    """The course's settings, with the book's values as defaults.

    Angles are in radians here; the node converts ``~angular_tolerance``
    from the degrees the book uses. A negative ``goal_distance`` drives
    backwards, a negative ``goal_angle`` turns clockwise.
    """

    # Upper bounds that no TurtleBot-class course needs; past them a value is
    # a typo (or a unit mix-up) and the robot must not move.
    MAX_LINEAR_SPEED = 2.0          # m/s
    MAX_ANGULAR_SPEED = 2 * math.pi  # rad/s
    MAX_LEGS = 1000

    # precise_gain (1/s) sets the approach: speed = gain * what remains,
    # clamped between the creep speed and the normal speed.
    # precise_heading_gain (1/s) turns heading error into a turn rate.
    def __init__(self, linear_speed=0.15, goal_distance=1.0,
                 angular_speed=0.5, goal_angle=math.pi,
                 angular_tolerance=math.radians(1.0), legs=2, pause=1.0,
                 precise=False, precise_gain=1.0, precise_heading_gain=4.0,
                 precise_min_linear_speed=0.005,
                 precise_min_angular_speed=0.01):
        self.linear_speed = linear_speed
        self.goal_distance = goal_distance
        self.angular_speed = angular_speed
        self.goal_angle = goal_angle
        self.angular_tolerance = angular_tolerance
        self.legs = legs
        self.pause = pause
        self.precise = precise
        self.precise_gain = precise_gain
        self.precise_heading_gain = precise_heading_gain
        self.precise_min_linear_speed = precise_min_linear_speed
        self.precise_min_angular_speed = precise_min_angular_speed

    def _checked(self):
        """(settings converted to their types, problems found) via params."""
        positive = dict(minimum=0.0, allow_zero=False)
        checks = (
            ('linear_speed', params.number,
             dict(maximum=self.MAX_LINEAR_SPEED, **positive)),
            ('angular_speed', params.number,
             dict(maximum=self.MAX_ANGULAR_SPEED, **positive)),
            ('goal_distance', params.number, {}),
            ('goal_angle', params.number, {}),
            ('angular_tolerance', params.number, dict(minimum=0.0)),
            ('pause', params.number, dict(minimum=0.0)),
            ('legs', params.integer, dict(minimum=1, maximum=self.MAX_LEGS)),
            ('precise', params.flag, {}),
            ('precise_gain', params.number, positive),
            ('precise_heading_gain', params.number, positive),
            ('precise_min_linear_speed', params.number,
             dict(maximum=self.MAX_LINEAR_SPEED, **positive)),
            ('precise_min_angular_speed', params.number,
             dict(maximum=self.MAX_ANGULAR_SPEED, **positive)),
        )
        values, found = {}, []
        for name, check, options in checks:
            try:
                values[name] = check(name, getattr(self, name), **options)
            except ValueError as err:
                found.append(str(err))
        return values, found

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


def expected_end_pose(start, config):
    """Where a perfect robot would end the course begun at ``start``."""
    x, y, yaw = start
    for _ in range(int(config.legs)):
        x += config.goal_distance * math.cos(yaw)
        y += config.goal_distance * math.sin(yaw)
        yaw += config.goal_angle
    return Pose2D(x, y, normalize_angle(yaw))


def pose_error(actual, expected):
    """(position error in m, heading error in rad) of one pose against another."""
    return (math.hypot(actual.x - expected.x, actual.y - expected.y),
            normalize_angle(actual.yaw - expected.yaw))


def _clamp(value, low, high):
    return max(low, min(high, value))


class OutAndBack(object):
    """Drive the out-and-back course one control cycle at a time.

    Call :meth:`update` with the latest pose and the time (seconds, any
    origin); it returns the :class:`Command` to send until the next call.
    :attr:`done` turns true after the last leg's pause; from then on every
    command is :data:`STOP`. :meth:`pop_events` hands over progress lines for
    the log.
    """

    def __init__(self, config=None):
        self.config = (config or CourseConfig()).validate()
        self.legs = int(self.config.legs)
        self.leg = 1
        self.phase = DRIVE
        self.start_pose = None
        self.start_time = None
        self.end_time = None
        self._now = None
        self._events = []
        self._after_pause = None
        self._pause_until = None
        self._leg_start = None
        self._phase_time = None
        self._last_yaw = None
        self.turned = 0.0
        self.distance = 0.0

    @property
    def done(self):
        """True once the whole course, final pause included, is over."""
        return self.phase == DONE

    @property
    def elapsed(self):
        """Seconds from the first update to the end (or to the last update)."""
        if self.start_time is None:
            return 0.0
        return (self.end_time if self.end_time is not None
                else self._now) - self.start_time

    def pop_events(self):
        """Progress messages produced since the last call, oldest first."""
        events, self._events = self._events, []
        return events

    def update(self, pose, now):
        """Advance the course with a new pose (Pose2D) at time ``now`` (s)."""
        pose = Pose2D(*(float(v) for v in pose))
        if not all(math.isfinite(v) for v in pose):
            raise ValueError('pose has a non-finite value: %r' % (pose,))
        now = float(now)
        if self.start_time is None:
            self.start_time = self._phase_time = now
            self.start_pose = pose
            self._begin_drive(pose, now)
        self._now = now
        if self._last_yaw is not None:
            self.turned += normalize_angle(pose.yaw - self._last_yaw)
            self._last_yaw = pose.yaw
        if self.phase == PAUSE and now >= self._pause_until:
            self._after_pause(pose, now)
        if self.phase == DRIVE:
            return self._drive(pose, now)
        if self.phase == TURN:
            return self._turn(pose, now)
        return STOP

    # --- phases ---------------------------------------------------------------

    def _label(self):
        return 'leg %d/%d' % (self.leg, self.legs)

    def _begin_drive(self, pose, now):
        self.phase, self._phase_time = DRIVE, now
        self._leg_start = pose
        self._last_yaw = None
        self.distance = 0.0

    def _drive(self, pose, now):
        cfg = self.config
        self.distance = math.hypot(pose.x - self._leg_start.x,
                                   pose.y - self._leg_start.y)
        remaining = abs(cfg.goal_distance) - self.distance
        if remaining <= 0.0:
            self._events.append('%s: drove %.3f m in %.1f s' % (
                self._label(), self.distance, now - self._phase_time))
            # Like the book, the turn is measured from the last reading of
            # the drive, so any rotation while stopping counts towards it.
            self.turned, self._last_yaw = 0.0, pose.yaw
            self._pause(now, self._begin_turn)
            return STOP
        speed, angular = cfg.linear_speed, 0.0
        if cfg.precise:
            speed = _clamp(cfg.precise_gain * remaining,
                           cfg.precise_min_linear_speed, cfg.linear_speed)
            heading_error = normalize_angle(pose.yaw - self._leg_start.yaw)
            angular = _clamp(-cfg.precise_heading_gain * heading_error,
                             -cfg.angular_speed, cfg.angular_speed)
        return Command(math.copysign(speed, cfg.goal_distance), angular)

    def _begin_turn(self, pose, now):
        self.phase, self._phase_time = TURN, now

    def _turn(self, pose, now):
        cfg = self.config
        direction = math.copysign(1.0, cfg.goal_angle)
        progress = self.turned * direction
        slack = 0.0 if cfg.precise else cfg.angular_tolerance
        remaining = abs(cfg.goal_angle) - progress
        if remaining - slack <= 0.0:
            self._events.append('%s: turned %.1f deg in %.1f s' % (
                self._label(), math.degrees(self.turned),
                now - self._phase_time))
            self._pause(now, self._end_leg)
            return STOP
        speed = cfg.angular_speed
        if cfg.precise:
            speed = _clamp(cfg.precise_gain * remaining,
                           cfg.precise_min_angular_speed, cfg.angular_speed)
        return Command(0.0, direction * speed)

    def _end_leg(self, pose, now):
        self._last_yaw = None
        if self.leg >= self.legs:
            self.phase, self.end_time = DONE, now
            self._events.append('course done in %.1f s' % (
                now - self.start_time))
        else:
            self.leg += 1
            self._begin_drive(pose, now)

    def _pause(self, now, then):
        self.phase = PAUSE
        self._pause_until = now + self.config.pause
        self._after_pause = then
