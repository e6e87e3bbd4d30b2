"""Riding out a link that drops out: Wi-Fi between a workstation and its robot.

A course steers by the robot's transform. When that stops updating for
``timeout`` seconds (~tf_timeout), or what arrives is stamped that long
ago (a link holding messages back), the link has dropped out, or the
driver is gone. :class:`Dropouts` tells the control loop what to do on
each tick:

* FRESH: steer as usual;
* HOLD: the transform is stale: command zero (the robot's own watchdog
  stops it anyway when the commands are lost too) and wait, up to
  ``grace`` seconds more (~link_grace), for it to come back; the course
  then carries on from the pose tf gives;
* LOST: stale for ``timeout + grace``: give up, robot stopped.

It counts the dropouts ridden out and their seconds, for the summary
line. Times are seconds on any one clock (ROS time in the nodes).
"""
from collections import namedtuple

FRESH, HOLD, LOST = 'fresh', 'hold', 'lost'

#: ``state`` is FRESH, HOLD or LOST; ``began`` is True on the tick a HOLD
#: begins; ``ended`` is the length (s) of a dropout that ended this tick
#: (FRESH again), else None; ``stale`` is the transform's age (s).
Tick = namedtuple('Tick', 'state began ended stale')


class Dropouts(object):
    """The transform's dropouts, tick by tick (see the module docstring)."""

    def __init__(self, timeout, grace):
        if not (timeout > 0.0 and grace >= 0.0):
            raise ValueError('timeout must be positive and grace not negative, '
                             'got %r and %r' % (timeout, grace))
        self.timeout = float(timeout)
        self.grace = float(grace)
        self.count = 0  # dropouts ridden out
        self.seconds = 0.0  # their length in all
        self._since = None  # when the transform was last fresh, in a dropout

    def tick(self, now, fresh_at, stamp=None):
        """The state at ``now``, the transform last updated at ``fresh_at``,
        its newest ``stamp`` (if known) no later: its age is from the
        earlier of the two."""
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

    @property
    def holding(self):
        """True during a dropout."""
        return self._since is not None

    def summary(self):
        """'never', or how many dropouts were ridden out and for how long."""
        if not self.count:
            return 'never'
        return '%d time%s, %.1f s in all' % (self.count, 's' * (self.count > 1),
                                             self.seconds)
