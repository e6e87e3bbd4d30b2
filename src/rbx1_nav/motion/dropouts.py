"""Riding out a link that drops out: Wi-Fi between a workstation and its robot.

A transform not updated for ``timeout`` s (~tf_timeout), or stamped that
long ago, means the link dropped out or the driver is gone. Each tick
:class:`Dropouts` says FRESH (steer), HOLD (command zero and wait up to
``grace`` s more, ~link_grace) or LOST (stale for ``timeout + grace``:
give up). Times are seconds on any one clock.
"""
from collections import namedtuple

FRESH, HOLD, LOST = 'fresh', 'hold', 'lost'

#: ``state`` is FRESH, HOLD or LOST; ``began`` is True on the tick a HOLD
#: begins; ``ended`` is the length (s) of a dropout that ended this tick
#: (FRESH again), else None; ``stale`` is the transform's age (s).
Tick = namedtuple('Tick', 'state began ended stale')


class Dropouts(object):
    """The transform's dropouts, tick by tick, and those ridden out."""

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
        """The Tick at ``now``; the transform's age counts from the earlier of
        its last update ``fresh_at`` and its newest ``stamp`` (if known)."""
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
