"""The course: a list of steps run one control cycle at a time, the logic of every motion node.

No rospy here: ``runner_ros`` calls :meth:`Course.update` each cycle, tests on a fake clock.
"""
import math
from collections import namedtuple

from rbx1_nav.motion.course.command import DONE, PAUSE, STOP, TURN
from rbx1_nav.motion.course.in_flight import InFlight
from rbx1_nav.motion.course.precise import Breakaway
from rbx1_nav.motion.course.stalls import Stalls
from rbx1_nav.motion.course.steps import Drive, Pause, TimedDrive, TimedTurn, Turn
from rbx1_nav.transform_utils import Pose2D, normalize_angle

__all__ = ['Course', 'LastReading', 'StepContext', 'legs_course']

LastReading = namedtuple('LastReading', 'stamp pose delay held')
LastReading.__doc__ = """What odometry said last: the pose last fed in, as read (before any
prediction), its stamp (s), the command delay assumed (s) and when the course last held (s)."""


class StepContext(object):
    """What the steps of one course read and write, in one place: ``yaw_total`` (unwrapped,
    since the start), ``motion_end_yaw`` (its value when the latest drive or turn ended),
    ``in_flight`` (the commands sent), ``stalls``, ``breakaway`` (precise mode's creep
    speeds), the last reading, and ``log(text)`` for progress lines."""

    def __init__(self, breakaway, log):
        self.yaw_total = self.motion_end_yaw = 0.0
        self.in_flight = InFlight()
        self.stalls = Stalls(self.in_flight)
        self.breakaway = breakaway
        self.log = log
        self.stamp = None  # of the pose last fed in (s)
        self.raw = None  # that pose, as read (before any prediction)
        self.held = -math.inf  # the last time the course held the robot (s)

    def reading(self):
        """What odometry said last: a :class:`LastReading`."""
        return LastReading(self.stamp, self.raw, self.in_flight.delay, self.held)

    def settled(self, sent, settle, longest):
        """True once the pose is stamped ``settle`` s after the robot ran the
        command sent at ``sent`` (s) and after the last motion measured, or
        ``longest`` s after it ran it (odometry that never reads zero)."""
        ran = sent + self.in_flight.delay
        still = max(ran, self.stalls.moved or ran) + settle
        return self.stamp >= min(still, ran + longest) - 1e-9


class Course(object):
    """Run steps one control cycle at a time (then STOP); what they share is a
    :class:`StepContext`. ``breakaway``: precise mode's creep speeds, shared by every course
    of one runner (a new precise.Breakaway if None)."""

    def __init__(self, steps, breakaway=None):
        self.steps = list(steps)
        if not self.steps:
            raise ValueError('a course needs at least one step')
        self.index = 0
        self.start_pose = self.start_time = self.end_time = None
        self._now = self._last_yaw = None
        self._events = []
        self.context = StepContext(breakaway or Breakaway(), self._events.append)
        self.precise = any(getattr(step, 'approach', None) for step in self.steps)

    @property
    def yaw_total(self):
        """The yaw (rad, unwrapped) turned since the start, after the end too."""
        return self.context.yaw_total

    @property
    def stalls(self):
        """The spells the robot stood still while commanded to move."""
        return self.context.stalls

    @property
    def breakaway(self):
        return self.context.breakaway

    @property
    def done(self):
        """True once the whole course, final pause included, is over."""
        return self.index >= len(self.steps)

    @property
    def turned(self):
        """The yaw (rad) the latest closed-loop turn measured; 0 before one."""
        for step in reversed(self.steps[:self.index + 1]):
            if step.kind == TURN and step.progress is not None:
                return step.progress
        return 0.0

    @property
    def phase(self):
        """'drive', 'turn', 'pause' (the current step's kind) or 'done'."""
        return DONE if self.done else self.steps[self.index].kind

    @property
    def elapsed(self):
        """Seconds from the first update to the end (or to the last update)."""
        if self.start_time is None:
            return 0.0
        return (self.end_time if self.end_time is not None else self._now) - self.start_time

    def pop_events(self):
        """Progress messages produced since the last call, oldest first."""
        events = list(self._events)
        del self._events[:]
        return events

    def ideal_end(self, start):
        """Where a perfect robot ends the course begun at ``start``."""
        pose = start
        for step in self.steps:
            pose = step.ideal_end(pose)
        return pose

    def update(self, pose, now, age=0.0):
        """The Command till the next call for a Pose2D ``age`` s old at ``now`` (s, any origin)."""
        pose, age = Pose2D(*(float(v) for v in pose)), float(age)
        if not all(math.isfinite(v) for v in pose + (age,)):
            raise ValueError('pose has a non-finite value: %r (age %r)' % (pose, age))
        now = float(now)
        context = self.context
        context.stamp, context.raw = now - age, pose
        context.in_flight.read(age)
        if self.precise:
            pose = context.in_flight.predict(pose, now, age)
        command = self._advance(pose, now)
        context.in_flight.record(now, command)
        return command

    def hold(self, now):
        """STOP at ``now`` (s) without a pose (a link dropout), recorded so
        predictions and the stall count know the robot was told to stop."""
        self._now = self.context.held = float(now)
        self.context.in_flight.record(self._now, STOP)
        return STOP

    def turned_after_end(self, yaw):
        """The robot turned ``yaw`` (rad) after the course ended, while it settled."""
        self.context.yaw_total += yaw

    def _advance(self, pose, now):
        """:meth:`update` with the pose to steer by."""
        context = self.context
        if self.start_time is None:
            self.start_time = now
            self.start_pose = pose
            self._last_yaw = pose.yaw
            self.steps[0].begin(context, pose, now)
        self._now = now
        context.yaw_total += normalize_angle(pose.yaw - self._last_yaw)
        self._last_yaw = pose.yaw
        while not self.done:
            step = self.steps[self.index]
            command = step.update(context, pose, now)
            if command is not None:
                return command
            if step.kind != PAUSE:
                context.motion_end_yaw = context.yaw_total
            self.index += 1
            if self.done:
                self.end_time = now
                context.log('course done in %.1f s' % (now - self.start_time))
                break
            self.steps[self.index].begin(context, pose, now)
            if step.kind != PAUSE:
                break  # a drive or turn ends on a cycle of stop
        return STOP


def legs_course(distance, angle, legs, linear_speed, angular_speed,
                tolerance=0.0, pause=0.0, approach=None, period=None):
    """[drive ``distance``, pause, turn ``angle``, pause] x ``legs``: closed loop on odometry, or
    open loop at a control ``period`` (s); ``tolerance`` (rad): turns'; ``approach``: precise."""
    if angle and tolerance >= abs(angle) and approach is None and period is None:
        raise ValueError('angular_tolerance (%g deg) must be smaller than the '
                         'turn (%g deg), or every turn ends before it starts'
                         % (math.degrees(tolerance), math.degrees(abs(angle))))
    steps = []
    for leg in range(1, int(legs) + 1):
        label = 'leg %d/%d' % (leg, legs)
        if period is None:
            drive = Drive(distance, linear_speed, approach=approach,
                          heading_rate=angular_speed, label=label)
            turn = Turn(angle, angular_speed, tolerance, approach, label=label)
        else:
            drive = TimedDrive(distance, linear_speed, period, label=label)
            turn = TimedTurn(angle, angular_speed, period, label=label)
        steps += [drive, Pause(pause), turn, Pause(pause)]
    return steps
