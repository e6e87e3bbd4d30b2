"""The steps a course is made of: drive a distance, turn an angle, pause.

No rospy here. As in the book, a turn sums ``normalize_angle`` of each change in yaw (so it
works across the +-pi wrap and for turns of pi or more) from where the previous drive or turn
ended (rotation while stopping counts); a closed-loop step ends ``tolerance`` short of its goal,
in its own direction, on a cycle that commands a stop.
"""
import math

from rbx1_nav.motion.course.command import DRIVE, MAX_ANGULAR_SPEED, PAUSE, STOP, TURN, Command, clamp
from rbx1_nav.motion.course.precise import PreciseMode
from rbx1_nav.transform_utils import Pose2D, normalize_angle

__all__ = ['Step', 'Pause', 'Drive', 'Turn', 'TimedDrive', 'TimedTurn', 'DRIVE_AXIS', 'TURN_AXIS']


class Step(object):
    """One primitive of a course: :meth:`begin` runs on the cycle the previous step ended,
    :meth:`update` on later ones (the Command to send, None once over); ``progress``: what a
    closed-loop step last measured. Each is given the course's ``context`` (a
    course.StepContext): all a step reads and writes besides its own fields."""

    kind = None
    progress = None

    def __init__(self, label=''):
        self.label = label
        self.began = None

    def begin(self, context, pose, now):
        self.began = now

    def update(self, context, pose, now):
        raise NotImplementedError

    def ideal_end(self, pose):
        """Where a perfect robot stands after this step, begun at ``pose``."""
        return pose

    def _event(self, context, text, now, note=''):
        context.log('%s%s in %.1f s%s' % (self.label + ': ' if self.label else '',
                                         text, now - self.began, note))


class Pause(Step):
    """Stand still for ``duration`` seconds."""

    kind = PAUSE

    def __init__(self, duration, label=''):
        Step.__init__(self, label)
        self.duration = float(duration)

    def update(self, context, pose, now):
        return STOP if now < self.began + self.duration else None


class _Axis(object):
    """What a drive or turn moves along: kind, command, wording, ideal end."""

    def __init__(self, kind, verb, command, size, ideal_end):
        self.kind, self.verb = kind, verb
        self.command, self.size, self.ideal_end = command, size, ideal_end


DRIVE_AXIS = _Axis(
    DRIVE, 'drove', command=lambda speed: Command(speed, 0.0),
    size=lambda metres: '%.3f m' % metres,
    ideal_end=lambda pose, goal: Pose2D(pose.x + goal * math.cos(pose.yaw),
                                        pose.y + goal * math.sin(pose.yaw), pose.yaw))

TURN_AXIS = _Axis(
    TURN, 'turned', command=lambda speed: Command(0.0, speed),
    size=lambda radians: '%.1f deg' % math.degrees(radians),
    ideal_end=lambda pose, goal: Pose2D(pose.x, pose.y, normalize_angle(pose.yaw + goal)))


class _Move(Step):
    """A drive or turn: a goal along ``axis`` (m or rad; negative: back, clockwise), a speed."""

    axis = None

    def __init__(self, goal, speed, label=''):
        Step.__init__(self, label)
        self.goal, self.speed = float(goal), abs(float(speed))

    @property
    def kind(self):
        return self.axis.kind

    def ideal_end(self, pose):
        return self.axis.ideal_end(pose, self.goal)


class _OnOdometry(_Move):
    """Closed loop on odometry. Subclasses define ``measure`` (progress), ``remaining`` (of the
    goal after it, negative past it), ``advance`` (progress between two poses) and ``moving``
    (the command at a signed speed along the goal)."""

    def __init__(self, goal, speed, tolerance, approach, label=''):
        _Move.__init__(self, goal, speed, label)
        self.tolerance = float(tolerance)
        self.approach = approach
        self.precise = PreciseMode(approach) if approach is not None else None

    def update(self, context, pose, now):
        self.progress = self.measure(context, pose)
        remaining = self.remaining(self.progress)
        if self.precise is not None:
            return self.precise.update(self, context, pose, now, remaining)
        if remaining - self.tolerance <= 0.0:
            return self.end(context, now)
        return self.moving(pose, self.speed)

    def end(self, context, now, corrections=0, missed=None):
        """Log the step's end (with its corrections); None."""
        note = ''
        if corrections:
            note = ' after %d correction%s' % (corrections, 's' * (corrections > 1))
        if missed is not None:
            note += ', still %s off' % self.axis.size(missed)
        self._event(context, '%s %s' % (self.axis.verb, self.axis.size(self.progress)), now, note)
        return None


class Drive(_OnOdometry):
    """Drive ``distance`` metres (negative: backwards) on odometry."""

    axis = DRIVE_AXIS

    def __init__(self, distance, speed, tolerance=0.0, approach=None,
                 heading_rate=MAX_ANGULAR_SPEED, label=''):
        _OnOdometry.__init__(self, distance, speed, tolerance, approach, label)
        self.heading_rate = float(heading_rate)  # precise mode's turn rate cap
        self.start = None

    def begin(self, context, pose, now):
        _OnOdometry.begin(self, context, pose, now)
        self.start = pose

    def measure(self, context, pose):
        """The straight-line distance from the start."""
        return math.hypot(pose.x - self.start.x, pose.y - self.start.y)

    def remaining(self, progress):
        return abs(self.goal) - progress

    def advance(self, before, after):
        """How much farther from the start ``after`` is than ``before``."""
        return (math.hypot(after.x - self.start.x, after.y - self.start.y)
                - math.hypot(before.x - self.start.x, before.y - self.start.y))

    def moving(self, pose, speed):
        angular = 0.0
        if self.approach:
            heading_error = normalize_angle(pose.yaw - self.start.yaw)
            angular = clamp(-self.approach.heading_gain * heading_error,
                            -self.heading_rate, self.heading_rate)
        return Command(math.copysign(1.0, self.goal) * speed, angular)


class Turn(_OnOdometry):
    """Turn ``angle`` radians (negative: clockwise) on odometry."""

    axis = TURN_AXIS

    def __init__(self, angle, speed, tolerance=0.0, approach=None, label=''):
        _OnOdometry.__init__(self, angle, speed, tolerance, approach, label)
        self.anchor = None

    def begin(self, context, pose, now):
        _OnOdometry.begin(self, context, pose, now)
        self.anchor = context.motion_end_yaw

    def measure(self, context, pose):
        """The yaw turned (unwrapped) since the previous drive or turn ended."""
        return context.yaw_total - self.anchor

    def remaining(self, progress):
        return abs(self.goal) - progress * math.copysign(1.0, self.goal)

    def advance(self, before, after):
        """The turn from ``before`` to ``after`` in the goal's direction."""
        return math.copysign(1.0, self.goal) * normalize_angle(after.yaw - before.yaw)

    def moving(self, pose, speed):
        return self.axis.command(math.copysign(1.0, self.goal) * speed)


class _Timed(_Move):
    """Open loop: the speed for |goal| / speed s from the first command, scaled on the last cycle
    to the time left (under one ``period``), so the amount is exact whatever the ticks' phase."""

    def __init__(self, goal, speed, period, label=''):
        _Move.__init__(self, goal, speed, label)
        self.period = float(period)
        self.first = None

    def update(self, context, pose, now):
        if self.first is None:
            self.first = now
        remaining = abs(self.goal) / self.speed - (now - self.first)
        if remaining <= 1e-9:
            self._event(context, '%s %s open loop'
                        % (self.axis.verb, self.axis.size(self.goal)), now)
            return None
        fraction = min(1.0, remaining / self.period)
        return self.axis.command(math.copysign(self.speed * fraction, self.goal))


class TimedDrive(_Timed):
    """Drive ``goal`` metres at ``speed`` for goal / speed seconds."""

    axis = DRIVE_AXIS


class TimedTurn(_Timed):
    """Turn ``goal`` radians at ``speed`` for goal / speed seconds."""

    axis = TURN_AXIS
