"""The pieces the runner's control loop (MotionRunner._drive) asks at each tick. No rospy:
times are ROS times (anything whose difference has ``to_sec()``), the log is passed in.

A link dropout (Wi-Fi between a workstation and its robot, or a driver gone): a transform not
updated for ``timeout`` s (~tf_timeout), or stamped that long ago. Each tick :class:`Dropouts`
says FRESH (steer), HOLD (command zero, wait up to ``grace`` s more, ~link_grace) or LOST
(``timeout + grace`` stale: give up), in seconds on any one clock; :class:`DropoutHold`
acts on it.
"""
from collections import namedtuple

from rbx1_nav.common.aborted import CourseAborted
from rbx1_nav.motion.course.settle import WAITING, delivered

__all__ = ['NewestTransform', 'Dropouts', 'DropoutHold', 'StallCheck', 'FinalStops', 'FRESH',
           'HOLD', 'LOST']

FRESH, HOLD, LOST = 'fresh', 'hold', 'lost'

#: ``state``: FRESH, HOLD or LOST; ``began``: a HOLD begins this tick; ``ended``: the length (s)
#: of a dropout this tick ended (FRESH again), else None; ``stale``: the transform's age (s).
Tick = namedtuple('Tick', 'state began ended stale')


class Dropouts(object):
    """The transform's dropouts, tick by tick, and those ridden out."""

    def __init__(self, timeout, grace):
        if not (timeout > 0.0 and grace >= 0.0):
            raise ValueError('timeout must be positive and grace not negative, '
                             'got %r and %r' % (timeout, grace))
        self.timeout, self.grace = float(timeout), float(grace)
        self.count = 0  # dropouts ridden out
        self.seconds = 0.0  # their length in all
        self._since = None  # when the transform was last fresh, in a dropout

    def tick(self, now, fresh_at, stamp=None):
        """The Tick at ``now``; the transform's age counts from the earlier of its last update
        ``fresh_at`` and its newest ``stamp`` (if known)."""
        if stamp is not None:
            fresh_at = min(fresh_at, stamp)
        stale = now - fresh_at
        if stale <= self.timeout:
            ended = None
            if self._since is not None:  # back: a dropout ridden out
                ended = now - self._since
                self.count += 1
                self.seconds += ended
                self._since = None
            return Tick(FRESH, False, ended, stale)
        began = self._since is None
        self._since = fresh_at
        state = LOST if stale > self.timeout + self.grace else HOLD
        return Tick(state, began and state == HOLD, None, stale)

    def summary(self):
        """'never', or how many dropouts were ridden out and for how long."""
        if not self.count:
            return 'never'
        return '%d time%s, %.1f s in all' % (self.count, 's' * (self.count > 1), self.seconds)


class NewestTransform(object):
    """The newest transform read: ``pose``, its ``stamp`` (None before the first), the tick
    ``fresh_at`` it came (or the first tick), and whether the last tick brought it (``fresh``)."""

    def __init__(self, pose=None):
        self.pose = pose
        self.stamp = self.fresh_at = None
        self.fresh = False

    def tick(self, now, reading):
        """Note what the tick at ``now`` read: (pose, stamp), or None."""
        if self.fresh_at is None:
            self.fresh_at = now
        self.fresh = reading is not None and (self.stamp is None or reading[1] > self.stamp)
        if self.fresh:
            self.pose, self.stamp = reading
            self.fresh_at = now

    def age(self, now):
        """Seconds from the transform's stamp to ``now``."""
        return (now - self.stamp).to_sec()


class DropoutHold(object):
    """One course's ride through stale transforms (:class:`Dropouts`): the robot held, or the
    course aborted past ~link_grace; ``where`` names the transform."""

    def __init__(self, name, where, timeout, grace, stop, warn, info):
        self.name, self.where, self.stop = name, where, stop
        self.warn, self.info = warn, info
        self.dropouts = Dropouts(timeout, grace)

    def held(self, now, reading):
        """True while the robot is to be held (commanded zero) at ``now``,
        by ``reading`` (a :class:`NewestTransform`); CourseAborted when lost."""
        stamp = None if reading.stamp is None else reading.stamp.to_sec()
        tick = self.dropouts.tick(now.to_sec(), reading.fresh_at.to_sec(), stamp)
        if tick.state == LOST:
            self.stop()
            raise CourseAborted(
                '%s (limit ~tf_timeout %.2f s + ~link_grace %.2f s): robot driver or '
                'simulator gone, or the link to the robot down? Stopped the robot.' % (
                    self._stale(now, reading, tick), self.dropouts.timeout, self.dropouts.grace))
        if tick.began:
            self.warn('%s: %s (~tf_timeout): a link dropout? Holding the robot '
                      '(zero velocity) and waiting up to ~link_grace %.1f s for it'
                      % (self.name, self._stale(now, reading, tick), self.dropouts.grace))
        elif tick.ended is not None:
            self.info('%s: %s is back after %.2f s; carrying on from where it says '
                      'the robot is' % (self.name, self.where, tick.ended))
        return tick.state == HOLD

    def _stale(self, now, reading, tick):
        """How the transform is stale: not updated, or stamped long ago."""
        if reading.fresh_at == now:
            return ('%s is %.2f s old by its stamp though still arriving (a link holding messages '
                    'back, or the robot\'s clock behind this one\'s?)' % (self.where, tick.stale))
        return '%s has not been updated for %.2f s' % (self.where, tick.stale)

    def summary(self):
        """The dropouts ridden out, for the summary line."""
        return self.dropouts.summary()


class StallCheck(object):
    """Feeds the robot's measured velocities to a course's stall count, warning of each spell."""

    def __init__(self, name, warn):
        self.name, self.warn = name, warn

    def check(self, course, start, velocities):
        """``velocities``: (stamp, linear, angular) in stamp order; ``start``: the first tick."""
        for stamp, linear, angular in velocities:
            spell = course.stalls.velocity((stamp - start).to_sec(), linear, angular)
            if spell is not None:
                self.warn('%s: the robot stood still for %.2f s while commanded to move: '
                          'stopped by its watchdog (commands late or lost on the way to it?) '
                          'or held (motors off, bumper)' % (self.name, spell))


class FinalStops(object):
    """After the last step: the robot commanded zero at every tick until ``settle`` (a
    motion.settle.Settle) has a still robot or gives up; the stops sent are counted, so a command
    still on a slow link (more bytes unacknowledged than the stops') is no still robot."""

    def __init__(self, settle, message_bytes):
        self.settle, self.message_bytes = settle, message_bytes
        self.stops = 0

    def done(self, held, reading, start, unacknowledged):
        """After a stop sent: True once settled or given up; ``held``: the transform is stale
        (the wait, on odometry's stamps, pauses); ``unacknowledged``: bytes (None: unknown)."""
        self.stops += 1
        sent = delivered(unacknowledged, self.stops, self.message_bytes)
        return (not held and reading.fresh and self.settle.update(
            reading.pose, (reading.stamp - start).to_sec(), sent) != WAITING)

    @property
    def waiting(self):
        return self.settle.state == WAITING
