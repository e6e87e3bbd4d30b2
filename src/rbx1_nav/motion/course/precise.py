"""Precise mode: how a closed-loop drive or turn ends within millimetres (docs/courses.md).

No rospy here. With an :class:`Approach`, a closed-loop step hands its cycles to a PreciseMode.
"""
import math
from collections import namedtuple

from rbx1_nav.common import params
from rbx1_nav.common.params import param
from rbx1_nav.motion.course.command import DRIVE, MAX_ANGULAR_SPEED, MAX_LINEAR_SPEED, STOP, TURN, clamp

__all__ = ['Approach', 'PRECISE_PARAMS', 'approach', 'Breakaway', 'PreciseMode']


Approach = namedtuple('Approach', 'gain heading_gain min_linear_speed min_angular_speed')
Approach.__doc__ = """Precise mode's settings (see PRECISE_PARAMS)."""

# Shared by every closed-loop course node.
PRECISE_PARAMS = (
    param('precise', False, params.flag,
          doc='slow down near each goal, hold heading, ignore the tolerance, '
              'check each goal on a still robot'),
    param('precise_gain', 1.0, params.number, '/s',
          'approach speed = gain x what remains', **params.POSITIVE),
    param('precise_heading_gain', 4.0, params.number, '/s',
          'turn rate per radian of heading error while driving', **params.POSITIVE),
    param('precise_min_linear_speed', 0.005, params.number, 'm/s',
          'creep speed near a distance goal', maximum=MAX_LINEAR_SPEED, **params.POSITIVE),
    param('precise_min_angular_speed', 0.01, params.number, 'rad/s',
          'creep speed near an angle goal', maximum=MAX_ANGULAR_SPEED, **params.POSITIVE),
)


def approach(values):
    """The :class:`Approach` of checked PRECISE_PARAMS values, or None."""
    if not values['precise']:
        return None
    return Approach(values['precise_gain'], values['precise_heading_gain'],
                    values['precise_min_linear_speed'], values['precise_min_angular_speed'])


class Breakaway(object):
    """Precise mode's creep speeds, raised where the robot will not move. Wheels stick below a
    breakaway speed (friction, a motor deadband, a skid-steer base turning on the spot): a creep
    that moved the robot under a tenth of itself for STILL s after it landed is raised FACTOR
    times (at most to the step's speed) until it moves; ``speeds`` keeps the minimum per kind
    for every later step and course sharing this object."""

    STILL = 0.5  # s
    FACTOR = 1.5

    def __init__(self):
        self.speeds = {DRIVE: 0.0, TURN: 0.0}  # the learned minima
        self.pending = {}  # kind: speed stalled at, until motion shows

    def raise_to(self, kind, stalled, speed):
        """The robot stood still at ``stalled``; creep at ``speed`` now."""
        self.pending.setdefault(kind, stalled)
        self.speeds[kind] = max(self.speeds[kind], speed)

    def moved(self, kind, log, unit):
        """The robot moved: log a new minimum once, through ``log``."""
        stalled = self.pending.pop(kind, None)
        if stalled is not None:
            name = 'linear' if kind == DRIVE else 'angular'
            log('precise mode: the robot stood still at %.4g %s and moved at %.4g %s, below its '
                'breakaway speed; creeping at %.4g %s or faster from now on (set '
                '~precise_min_%s_speed to it to start there)'
                % (stalled, unit, self.speeds[kind], unit, self.speeds[kind], unit, name))


class PreciseMode(object):
    """Precise mode of one closed-loop step: approach, check, correct, unstick. Past the goal it
    stops and checks on a still robot (``StepContext.settled``); a goal missed by more than CHECK s
    of creep is approached again, from whichever side, at most MAX_CORRECTIONS times (a late
    stop on a slow link, a robot that coasts)."""

    SETTLE = 0.1  # s
    LONGEST = 1.0  # s
    CHECK = 0.1  # s of creep
    MAX_CORRECTIONS = 3

    def __init__(self, approach):
        self.approach = approach
        self.sense = 1.0  # 1: short of the goal; -1: back from past it
        self.stopped = None  # when the stop to check was sent
        self.corrections = 0
        self.mark = None  # (time sent, pose): where a stall watch began

    def update(self, step, context, pose, now, remaining):
        """The command for ``step``, ``remaining`` short of its goal; None: over."""
        if self.stopped is None:
            if remaining * self.sense > 0.0:
                return self._close_in(step, context, pose, now, remaining)
            self.stopped, self.mark = now, None
        if not context.settled(self.stopped, self.SETTLE, self.LONGEST):
            return STOP
        if abs(remaining) <= self.creep(step, context.breakaway) * self.CHECK:
            return step.end(context, now, self.corrections)
        if self.corrections == self.MAX_CORRECTIONS:
            return step.end(context, now, self.corrections, remaining)
        self.corrections += 1
        self.stopped, self.sense = None, math.copysign(1.0, remaining)
        return self._close_in(step, context, pose, now, remaining)

    def _close_in(self, step, context, pose, now, remaining):
        """Move towards the goal (in ``sense``), slowing down near it."""
        speed = clamp(self.approach.gain * abs(remaining),
                      self.creep(step, context.breakaway), step.speed)
        speed = self._unstick(step, context, now, speed)
        return step.moving(pose, self.sense * speed)

    def creep(self, step, breakaway):
        """The creep speed, or the learned breakaway one, at most the step's."""
        minimum = (self.approach.min_linear_speed if step.kind == DRIVE
                   else self.approach.min_angular_speed)
        return min(step.speed, max(minimum, breakaway.speeds[step.kind]))

    def _unstick(self, step, context, now, speed):
        """``speed``, raised where poses read (not predicted) show the robot still (Breakaway)."""
        read = context.reading()
        mark = self.mark
        if mark is None or read.held >= mark[0]:  # a new watch
            self.mark = (now, read.pose)
            return speed
        elapsed = read.stamp - (mark[0] + read.delay)  # since it landed
        if elapsed < Breakaway.STILL:
            return speed
        self.mark = (now, read.pose)
        unit = 'm/s' if step.kind == DRIVE else 'rad/s'
        if self.sense * step.advance(mark[1], read.pose) >= 0.1 * speed * elapsed:
            context.breakaway.moved(step.kind, context.log, unit)
            return speed
        if speed >= step.speed:
            return speed  # not a creep: a watchdog or a bumper (Stalls)
        raised = min(step.speed, Breakaway.FACTOR * speed)
        context.breakaway.raise_to(step.kind, speed, raised)
        context.stalls.excuse(read.stamp + Breakaway.STILL)
        return raised
