"""Motion primitives and the course that runs them: the logic of every motion node.

No rospy here. A course is a list of steps, run one after the other:

* :class:`Drive` a distance and :class:`Turn` an angle, closed loop on
  odometry (the pose fed in each cycle);
* :class:`TimedDrive` and :class:`TimedTurn`, open loop on time: the
  speed for ``distance / speed`` seconds, as the book's timed course does;
* :class:`Pause`, the robot stopped for a time.

The ROS side (``rbx1_nav.motion.runner_ros``) calls :meth:`Course.update` once per
control cycle with the latest pose and ROS time and publishes the
:class:`Command` it returns; tests drive the same class with a simulated
robot and a fake clock. The book's courses are lists of these steps:
out-and-back is [drive 1 m, turn pi] x 2, the square [drive 1 m, turn
pi/2] x 4, a linear calibration [drive d], an angular one [turn 2 pi].

Rules shared by every course, as in the book:

* a drive measures the straight-line distance from where it began;
* a turn adds up ``normalize_angle`` of each change in yaw, so it works
  across the +-pi wrap and for turns of pi or more, and counts from where
  the previous drive or turn ended (rotation while stopping counts);
* a closed-loop step ends once it has reached its goal less its
  ``tolerance`` (measured in the step's own direction, so a clockwise turn
  stops equally early); the cycle that ends it commands a stop;
* precise mode (an :class:`Approach`) slows down near each goal (speed
  proportional to what remains, never below a creep speed), holds the
  drive's starting heading, and ignores the tolerance; it also steers by
  where the robot will be when its command lands, not by where an old pose
  says it was (:class:`InFlight`), and checks each goal once the robot
  stands still, going back or on when it missed (``_OnOdometry``); and it
  raises its creep speed where the robot will not move at it
  (:class:`Breakaway`).
"""
import bisect
import math
from collections import deque, namedtuple

from rbx1_nav.common import params
from rbx1_nav.common.geometry import arc_step
from rbx1_nav.common.params import param
from rbx1_nav.transform_utils import Pose2D, normalize_angle

__all__ = ['Command', 'STOP', 'Approach', 'Drive', 'Turn', 'TimedDrive',
           'TimedTurn', 'Pause', 'Course', 'InFlight', 'Stalls', 'Breakaway',
           'legs_course',
           'pose_error', 'MAX_LINEAR_SPEED', 'MAX_ANGULAR_SPEED', 'PRECISE_PARAMS',
           'approach', 'legs_params']

Command = namedtuple('Command', 'linear angular')
Command.__doc__ = 'A velocity command: forward speed (m/s), turn rate (rad/s).'

STOP = Command(0.0, 0.0)

DRIVE, TURN, PAUSE, DONE = 'drive', 'turn', 'pause', 'done'

# Upper bounds that no TurtleBot-class course needs; past them a value is a
# typo (or a unit mix-up) and the robot must not move.
MAX_LINEAR_SPEED = 2.0           # m/s
MAX_ANGULAR_SPEED = 2 * math.pi  # rad/s
MAX_DISTANCE = 100.0             # m, one drive
MAX_ANGLE = 4 * math.pi          # rad, one turn (two full turns)
MAX_TOLERANCE = math.pi / 2      # rad


Approach = namedtuple('Approach', 'gain heading_gain min_linear_speed '
                                  'min_angular_speed')
Approach.__doc__ = """Precise mode's settings.

gain (1/s): speed = gain * what remains, clamped between the creep speed
(min_linear_speed m/s, min_angular_speed rad/s) and the step's speed;
heading_gain (1/s) turns a drive's heading error into a turn rate.
"""


# Precise mode's settings, shared by every closed-loop course node.
PRECISE_PARAMS = (
    param('precise', False, params.flag,
          doc='slow down near each goal, hold heading, ignore the tolerance, '
              'check each goal on a still robot'),
    param('precise_gain', 1.0, params.number, '/s',
          'approach speed = gain x what remains', **params.POSITIVE),
    param('precise_heading_gain', 4.0, params.number, '/s',
          'turn rate per radian of heading error while driving', **params.POSITIVE),
    param('precise_min_linear_speed', 0.005, params.number, 'm/s',
          'creep speed near a distance goal', maximum=MAX_LINEAR_SPEED,
          **params.POSITIVE),
    param('precise_min_angular_speed', 0.01, params.number, 'rad/s',
          'creep speed near an angle goal', maximum=MAX_ANGULAR_SPEED,
          **params.POSITIVE),
)


def approach(values):
    """The :class:`Approach` of checked PRECISE_PARAMS values, or None."""
    if not values['precise']:
        return None
    return Approach(values['precise_gain'], values['precise_heading_gain'],
                    values['precise_min_linear_speed'],
                    values['precise_min_angular_speed'])


def legs_params(linear_speed, goal_distance, angular_speed, goal_angle,
                angle_unit='rad', angular_tolerance=None, tolerance_unit='deg',
                legs=None, pause=1.0):
    """The parameters of a :func:`legs_course`, with these defaults.

    ``goal_angle`` is in ``angle_unit``, ``angular_tolerance`` in
    ``tolerance_unit`` ('rad' or 'deg'; the book's nodes use degrees for
    the tolerance); a tolerance or leg count of None is not a parameter.
    """
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
              'turn after each leg (negative: clockwise)',
              minimum=-max_angle, maximum=max_angle),
    ]
    if angular_tolerance is not None:
        specs.append(param('angular_tolerance', angular_tolerance,
                           params.number, tolerance_unit,
                           'a turn stops this much short', minimum=0.0,
                           maximum=in_unit(MAX_TOLERANCE, tolerance_unit)))
    if legs is not None:
        specs.append(param('legs', legs, params.integer, '', 'number of legs',
                           minimum=1, maximum=1000))
    specs.append(param('pause', pause, params.number, 's',
                       'stop after each drive and turn', minimum=0.0))
    return tuple(specs)


def pose_error(actual, expected):
    """(position error in m, heading error in rad) of one pose against another."""
    return (math.hypot(actual.x - expected.x, actual.y - expected.y),
            normalize_angle(actual.yaw - expected.yaw))


def _clamp(value, low, high):
    return max(low, min(high, value))


class Step(object):
    """One primitive of a course; subclasses fill in the behaviour.

    :meth:`begin` is called when the step becomes current (the cycle the
    previous one ended), :meth:`update` every cycle from the next one on.
    ``update`` returns the Command to send, or None when the step is over.
    """

    kind = None

    def __init__(self, label=''):
        self.label = label
        self.began = None

    def begin(self, course, pose, now):
        self.began = now

    def update(self, course, pose, now):
        raise NotImplementedError

    def ideal_end(self, pose):
        """Where a perfect robot stands after this step, begun at ``pose``."""
        return pose

    def _event(self, course, text, now, note=''):
        course.log('%s%s in %.1f s%s' % (self.label + ': ' if self.label else '',
                                         text, now - self.began, note))


class Pause(Step):
    """Stand still for ``duration`` seconds."""

    kind = PAUSE

    def __init__(self, duration, label=''):
        Step.__init__(self, label)
        self.duration = float(duration)

    def update(self, course, pose, now):
        return STOP if now < self.began + self.duration else None


class _Drive(Step):
    """What every drive has: a goal (m, negative: backwards) and a speed."""

    kind, verb = DRIVE, 'drove'

    def __init__(self, distance, speed, label=''):
        Step.__init__(self, label)
        self.goal, self.speed = float(distance), abs(float(speed))

    @staticmethod
    def command(speed):
        return Command(speed, 0.0)

    @staticmethod
    def size(metres):
        return '%.3f m' % metres

    def ideal_end(self, pose):
        return Pose2D(pose.x + self.goal * math.cos(pose.yaw),
                      pose.y + self.goal * math.sin(pose.yaw), pose.yaw)


class _Turn(Step):
    """What every turn has: a goal (rad, negative: clockwise) and a speed."""

    kind, verb = TURN, 'turned'

    def __init__(self, angle, speed, label=''):
        Step.__init__(self, label)
        self.goal, self.speed = float(angle), abs(float(speed))

    @staticmethod
    def command(speed):
        return Command(0.0, speed)

    @staticmethod
    def size(radians):
        return '%.1f deg' % math.degrees(radians)

    def ideal_end(self, pose):
        return Pose2D(pose.x, pose.y, normalize_angle(pose.yaw + self.goal))


class Breakaway(object):
    """Precise mode's creep speeds, raised where the robot will not move.

    Real wheels stick below a breakaway speed (static friction, a motor
    deadband; a skid-steer base turning on the spot needs far more), and a
    precise step creeping below it would wait for ever. When a precise
    step slowing down to its goal has commanded a speed below its own for
    STILL s since the command reached the robot, and odometry moved under a
    tenth of that (as :class:`Stalls` counts a stall), the step raises its
    creep speed to FACTOR times the command (at most the step's speed), and
    again until the robot moves. Then the course logs the new minimum once,
    and every later drive (or turn) of the course creeps at it or faster:
    ``speeds`` holds it per kind. A runner hands the same object to each
    course it drives, so later courses keep it too.
    """

    STILL = 0.5  # s
    FACTOR = 1.5

    def __init__(self):
        self.speeds = {DRIVE: 0.0, TURN: 0.0}  # the learned minima
        self.pending = {}  # kind: speed stalled at, until motion shows

    def raise_to(self, kind, stalled, speed):
        """The robot stood still at ``stalled``; creep at ``speed`` now."""
        self.pending.setdefault(kind, stalled)
        self.speeds[kind] = max(self.speeds[kind], speed)

    def moved(self, kind, course, unit):
        """The robot moved: log a new minimum once."""
        stalled = self.pending.pop(kind, None)
        if stalled is not None:
            name = 'linear' if kind == DRIVE else 'angular'
            course.log('precise mode: the robot stood still at %.4g %s and '
                       'moved at %.4g %s, below its breakaway speed; creeping '
                       'at %.4g %s or faster from now on (set '
                       '~precise_min_%s_speed to it to start there)'
                       % (stalled, unit, self.speeds[kind], unit,
                          self.speeds[kind], unit, name))


class _OnOdometry(object):
    """Closed loop on odometry: a mixin for Drive and Turn.

    They define ``remaining`` (what is left of the goal, negative past it),
    ``moving`` (the command at a speed along the goal, negative: back),
    ``advance`` (the progress between two poses) and ``approach``'s creep
    speed. Precise mode raises a creep speed the robot will not move at
    (:class:`Breakaway`) and checks each goal
    on a still robot: once the stop it sent at the goal has reached the
    robot and SETTLE s have passed since the last motion its odometry
    showed (LONGEST s at most), a goal missed by more than CHECK s of creep
    is approached again, from whichever side, at most MAX_CORRECTIONS
    times (a late stop on a slow link, a robot that coasts).
    """

    SETTLE = 0.1  # s
    LONGEST = 1.0  # s
    CHECK = 0.1  # s of creep
    MAX_CORRECTIONS = 3

    def __init__(self, tolerance, approach):
        self.tolerance = float(tolerance)
        self.approach = approach
        self.sense = 1.0  # 1: short of the goal; -1: back from past it
        self.stopped = None  # when precise mode sent the stop to check
        self.corrections = 0
        self.mark = None  # (time sent, pose): where a stall watch began

    def update(self, course, pose, now):
        remaining = self.remaining(course, pose)
        ap = self.approach
        if ap is None:
            if remaining - self.tolerance <= 0.0:
                return self._end(course, now)
            return self.moving(course, pose, self.speed)
        if self.stopped is None:
            if remaining * self.sense > 0.0:
                speed = _clamp(ap.gain * abs(remaining), self.creep(course),
                               self.speed)
                speed = self._unstick(course, now, speed)
                return self.moving(course, pose, self.sense * speed)
            self.stopped, self.mark = now, None
        if not course.settled(self.stopped, self.SETTLE, self.LONGEST):
            return STOP
        if abs(remaining) <= self.creep(course) * self.CHECK:
            return self._end(course, now)
        if self.corrections == self.MAX_CORRECTIONS:
            return self._end(course, now, remaining)
        self.corrections += 1
        self.stopped, self.sense = None, math.copysign(1.0, remaining)
        return self.update(course, pose, now)

    def creep(self, course):
        """The creep speed: precise mode's, or the breakaway speed learned
        (:class:`Breakaway`), at most the step's speed."""
        minimum = (self.approach.min_linear_speed if self.kind == DRIVE
                   else self.approach.min_angular_speed)
        return min(self.speed, max(minimum, course.breakaway.speeds[self.kind]))

    def _unstick(self, course, now, speed):
        """``speed``, or more where the robot stood still at it
        (:class:`Breakaway`), judged on the poses odometry gave, not on
        their predictions."""
        mark = self.mark
        if mark is None or course.held >= mark[0]:  # a new watch
            self.mark = (now, course.raw)
            return speed
        landed = mark[0] + course.in_flight.delay
        elapsed = course.stamp - landed
        if elapsed < Breakaway.STILL:
            return speed
        self.mark = (now, course.raw)
        unit = 'm/s' if self.kind == DRIVE else 'rad/s'
        if self.sense * self.advance(mark[1], course.raw) >= 0.1 * speed * elapsed:
            course.breakaway.moved(self.kind, course, unit)
            return speed
        if speed >= self.speed:
            return speed  # not a creep: a watchdog or a bumper (Stalls)
        raised = min(self.speed, Breakaway.FACTOR * speed)
        course.breakaway.raise_to(self.kind, speed, raised)
        course.stalls.excuse(course.stamp + Breakaway.STILL)
        return raised

    def _end(self, course, now, missed=None):
        """Log the step's end (with its corrections) and end it."""
        note = ''
        if self.corrections:
            note = ' after %d correction%s' % (self.corrections,
                                               's' * (self.corrections > 1))
        if missed is not None:
            note += ', still %s off' % self.size(missed)
        self._event(course, '%s %s' % (self.verb, self.size(self.done(course))),
                    now, note)
        return None


class Drive(_OnOdometry, _Drive):
    """Drive ``distance`` metres (negative: backwards) on odometry."""

    def __init__(self, distance, speed, tolerance=0.0, approach=None,
                 heading_rate=MAX_ANGULAR_SPEED, label=''):
        _Drive.__init__(self, distance, speed, label)
        _OnOdometry.__init__(self, tolerance, approach)
        self.heading_rate = float(heading_rate)  # precise mode's turn rate cap
        self.start = None

    def begin(self, course, pose, now):
        Step.begin(self, course, pose, now)
        self.start = pose

    def remaining(self, course, pose):
        course.distance = math.hypot(pose.x - self.start.x,
                                     pose.y - self.start.y)
        return abs(self.goal) - course.distance

    @staticmethod
    def done(course):
        return course.distance

    def advance(self, before, after):
        """How much farther from the start ``after`` is than ``before``."""
        return (math.hypot(after.x - self.start.x, after.y - self.start.y)
                - math.hypot(before.x - self.start.x, before.y - self.start.y))

    def moving(self, course, pose, speed):
        angular = 0.0
        if self.approach:
            heading_error = normalize_angle(pose.yaw - self.start.yaw)
            angular = _clamp(-self.approach.heading_gain * heading_error,
                             -self.heading_rate, self.heading_rate)
        return Command(math.copysign(1.0, self.goal) * speed, angular)


class Turn(_OnOdometry, _Turn):
    """Turn ``angle`` radians (negative: clockwise) on odometry."""

    def __init__(self, angle, speed, tolerance=0.0, approach=None, label=''):
        _Turn.__init__(self, angle, speed, label)
        _OnOdometry.__init__(self, tolerance, approach)
        self.anchor = None

    def begin(self, course, pose, now):
        Step.begin(self, course, pose, now)
        self.anchor = course.motion_end_yaw

    def remaining(self, course, pose):
        course.turned = course.yaw_total - self.anchor
        return abs(self.goal) - course.turned * math.copysign(1.0, self.goal)

    @staticmethod
    def done(course):
        return course.turned

    def advance(self, before, after):
        """The turn from ``before`` to ``after`` in the goal's direction."""
        return math.copysign(1.0, self.goal) * normalize_angle(after.yaw - before.yaw)

    def moving(self, course, pose, speed):
        return self.command(math.copysign(1.0, self.goal) * speed)


class _Timed(object):
    """Open loop: the step's speed for |goal| / speed seconds of ROS time.

    A mixin for _Drive and _Turn. The clock starts at the step's first
    command. The last cycle commands the fraction of the speed that the
    remaining time (less than one ``period``) calls for, so the commanded
    distance or angle is exact whatever the phase of the control ticks.
    """

    def __init__(self, period):
        self.period = float(period)
        self.first = None

    def update(self, course, pose, now):
        if self.first is None:
            self.first = now
        remaining = abs(self.goal) / self.speed - (now - self.first)
        if remaining <= 1e-9:
            self._event(course, '%s %s open loop' % (self.verb, self.size(self.goal)),
                        now)
            return None
        fraction = min(1.0, remaining / self.period)
        return self.command(math.copysign(self.speed * fraction, self.goal))


class TimedDrive(_Timed, _Drive):
    """Drive ``distance`` at ``speed`` for distance / speed seconds."""

    def __init__(self, distance, speed, period, label=''):
        _Drive.__init__(self, distance, speed, label)
        _Timed.__init__(self, period)


class TimedTurn(_Timed, _Turn):
    """Turn ``angle`` at ``speed`` for angle / speed seconds."""

    def __init__(self, angle, speed, period, label=''):
        _Turn.__init__(self, angle, speed, label)
        _Timed.__init__(self, period)


class InFlight(object):
    """The commands sent, and where they will have taken the robot.

    A pose read over a slow link is ``age`` seconds old, and the command
    sent now takes effect some ``delay`` later. From the pose's stamp until
    then the robot follows the commands sent from ``stamp - delay`` until
    now: :meth:`predict` adds their arcs onto the pose. The pose alone
    cannot tell the command delay, so it is taken as the link's delay the
    other way: the smallest age of the last ``memory`` readings (a reading
    is older than the link's delay when it waited for the control tick).
    """

    KEEP = 10.0  # s of commands kept

    def __init__(self, memory=20):
        self.sent = []  # (time sent, Command), oldest first
        self.times = []  # the times of self.sent, for bisect
        self.ages = deque(maxlen=memory)

    @property
    def delay(self):
        """The command delay assumed (s)."""
        return min(self.ages, default=0.0)

    def read(self, age):
        """A pose ``age`` s old was read."""
        self.ages.append(max(0.0, age))

    def record(self, now, command):
        """The command sent at ``now`` (s)."""
        self.sent.append((now, command))
        self.times.append(now)
        while len(self.sent) > 1 and self.times[1] < now - self.KEEP:
            del self.sent[0], self.times[0]

    def command_at(self, when):
        """The command the robot runs at ``when`` (s): the last one sent
        by ``when - delay``; STOP before the first."""
        ran = bisect.bisect_right(self.times, when - self.delay)
        return self.sent[ran - 1][1] if ran else STOP

    def predict(self, pose, now, age):
        """``pose``, read at ``now`` and ``age`` s old, moved on by the
        commands in flight."""
        start = now - age - self.delay
        ends = [t for t, _ in self.sent[1:]] + [now]
        for (sent, command), end in zip(self.sent, ends):
            seconds = min(end, now) - max(sent, start)
            if seconds > 0.0:
                pose = arc_step(pose, command.linear * seconds,
                                command.angular * seconds)
        return pose


class Stalls(object):
    """Spells when the robot stood still while its commands moved it.

    A robot's watchdog stops it when commands stop arriving (lost or late
    on the link); motors switched off or a bumper hold it too. Fed the
    velocity the robot's odometry measured, this counts the spells of at
    least ``minimum`` seconds when every commanded speed (of the command
    :class:`InFlight` says the robot runs then) was measured at under a
    tenth of itself. ``moved`` is the stamp of the latest velocity that
    was not standing still (over 0.1 mm/s or 0.01 deg/s), None before.
    """

    STILL = (1e-4, 2e-4)  # m/s, rad/s

    def __init__(self, in_flight, minimum=0.1):
        self.in_flight = in_flight
        self.minimum = minimum
        self.count = 0
        self.seconds = 0.0
        self.since = None  # start of the current spell
        self.moved = None
        self.excused = -math.inf  # a spell counts from here on at the earliest

    def velocity(self, stamp, linear, angular):
        """The robot's measured velocity at ``stamp`` (s); returns the
        length of a spell that just ended (s), else None."""
        if abs(linear) > self.STILL[0] or abs(angular) > self.STILL[1]:
            self.moved = max(stamp, self.moved or stamp)
        commanded = self.in_flight.command_at(stamp)
        pairs = [(abs(m), abs(c)) for m, c in ((linear, commanded.linear),
                                               (angular, commanded.angular)) if c]
        if pairs and all(measured < 0.1 * command for measured, command in pairs):
            if self.since is None:
                self.since = stamp
            return None
        return self.end(stamp)

    def excuse(self, until):
        """Standing still until ``until`` (s) is explained (precise mode
        found the robot's breakaway speed): not a spell."""
        self.excused = max(self.excused, until)

    def end(self, stamp):
        """Close a spell at ``stamp``; its length (s) if it counts, else None."""
        since, self.since = self.since, None
        if since is not None:
            since = max(since, self.excused)
        if since is None or stamp - since < self.minimum:
            return None
        self.count += 1
        self.seconds += stamp - since
        return stamp - since


class Course(object):
    """Run a list of steps one control cycle at a time.

    Call :meth:`update` with the latest pose and the time (seconds, any
    origin); it returns the :class:`Command` to send until the next call.
    :attr:`done` turns true after the last step; from then on every command
    is :data:`STOP`. :meth:`pop_events` hands over progress lines for the
    log. ``yaw_total`` is the yaw turned since the start (unwrapped),
    ``turned`` and ``distance`` the progress of the latest turn and drive.
    ``in_flight`` holds the commands it returned; a course with a precise
    step steers by its predictions. ``stalls`` counts the spells the robot
    stood still while commanded to move, from the velocities fed to it;
    ``breakaway`` holds the creep speeds precise steps learned
    (:class:`Breakaway`; a runner may set its own before the first update).
    """

    def __init__(self, steps):
        self.steps = list(steps)
        if not self.steps:
            raise ValueError('a course needs at least one step')
        self.index = 0
        self.start_pose = None
        self.start_time = None
        self.end_time = None
        self._now = None
        self._events = []
        self._last_yaw = None
        self.yaw_total = 0.0
        self.motion_end_yaw = 0.0
        self.turned = 0.0
        self.distance = 0.0
        self.stamp = None  # of the pose last fed in (s)
        self.raw = None  # that pose, as read (before any prediction)
        self.held = -math.inf  # the last time hold() was called (s)
        self.predicts = any(getattr(step, 'approach', None) for step in self.steps)
        self.in_flight = InFlight()
        self.stalls = Stalls(self.in_flight)
        self.breakaway = Breakaway()

    @property
    def done(self):
        """True once the whole course, final pause included, is over."""
        return self.index >= len(self.steps)

    @property
    def phase(self):
        """'drive', 'turn', 'pause' (the current step's kind) or 'done'."""
        return DONE if self.done else self.steps[self.index].kind

    @property
    def elapsed(self):
        """Seconds from the first update to the end (or to the last update)."""
        if self.start_time is None:
            return 0.0
        return (self.end_time if self.end_time is not None
                else self._now) - self.start_time

    def log(self, text):
        """Queue a progress line (steps report through this)."""
        self._events.append(text)

    def pop_events(self):
        """Progress messages produced since the last call, oldest first."""
        events, self._events = self._events, []
        return events

    def ideal_end(self, start):
        """Where a perfect robot ends the course begun at ``start``."""
        pose = start
        for step in self.steps:
            pose = step.ideal_end(pose)
        return pose

    def update(self, pose, now, age=0.0):
        """Advance the course with a new pose (Pose2D) at time ``now`` (s);
        ``age`` (s) is how old the pose is."""
        pose, age = Pose2D(*(float(v) for v in pose)), float(age)
        if not all(math.isfinite(v) for v in pose + (age,)):
            raise ValueError('pose has a non-finite value: %r (age %r)'
                             % (pose, age))
        now = float(now)
        self.stamp, self.raw = now - age, pose
        self.in_flight.read(age)
        if self.predicts:
            pose = self.in_flight.predict(pose, now, age)
        command = self._advance(pose, now)
        self.in_flight.record(now, command)
        return command

    def hold(self, now):
        """STOP at ``now`` (s) without a pose: the transform is stale (a
        link dropout). Recorded like any command, so predictions and the
        stall count know the robot was told to stand still."""
        self._now = self.held = float(now)
        self.in_flight.record(self._now, STOP)
        return STOP

    def settled(self, sent, settle, longest):
        """True once the pose steered by is stamped ``settle`` s after the
        robot ran the command sent at ``sent`` (s) and after the last motion
        its measured velocities showed (see :class:`Stalls`), or ``longest``
        s after it ran the command (odometry that never reads zero)."""
        ran = sent + self.in_flight.delay
        still = max(ran, self.stalls.moved or ran) + settle
        return self.stamp >= min(still, ran + longest) - 1e-9

    def _advance(self, pose, now):
        """:meth:`update` with the pose to steer by."""
        if self.start_time is None:
            self.start_time = now
            self.start_pose = pose
            self._last_yaw = pose.yaw
            self.steps[0].begin(self, pose, now)
        self._now = now
        self.yaw_total += normalize_angle(pose.yaw - self._last_yaw)
        self._last_yaw = pose.yaw
        while not self.done:
            step = self.steps[self.index]
            command = step.update(self, pose, now)
            if command is not None:
                return command
            if step.kind != PAUSE:
                self.motion_end_yaw = self.yaw_total
            self.index += 1
            if self.done:
                self.end_time = now
                self.log('course done in %.1f s' % (now - self.start_time))
                break
            self.steps[self.index].begin(self, pose, now)
            if step.kind != PAUSE:
                break  # a drive or turn ends on a cycle of stop
        return STOP


def legs_course(distance, angle, legs, linear_speed, angular_speed,
                tolerance=0.0, pause=0.0, approach=None, period=None):
    """[drive ``distance``, pause, turn ``angle``, pause] x ``legs``.

    Closed loop on odometry; with a control ``period`` (s), open loop on
    time instead. ``tolerance`` (rad) applies to closed-loop turns, as in
    the book; ``approach`` (an :class:`Approach`) selects precise mode.
    """
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


def control_rates(times):
    """(mean Hz, ticks in the slowest whole second) of control ticks at
    ``times`` (seconds, ascending); (0.0, 0) for fewer than two ticks.

    A node that falls behind its clock misses ticks: the slowest second
    shows it even when the mean looks fine.
    """
    if len(times) < 2:
        return 0.0, 0
    span = times[-1] - times[0]
    mean = (len(times) - 1) / span if span > 0 else 0.0
    whole = int(span)
    if whole < 1:
        return mean, len(times)
    counts = [0] * whole
    for t in times:
        second = int(t - times[0] + 1e-6)  # a tick on a whole second is in it
        if second < whole:
            counts[second] += 1
    return mean, min(counts)
