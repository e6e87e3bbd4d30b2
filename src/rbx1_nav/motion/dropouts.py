"""Riding out a link that drops out: Wi-Fi between a workstation and its robot.

A transform not updated for ``timeout`` s (~tf_timeout), or stamped that long ago, means a link
dropout or a driver gone. Each tick :class:`Dropouts` says FRESH (steer), HOLD (command zero,
wait up to ``grace`` s more, ~link_grace) or LOST (``timeout + grace`` stale: give up). Times
are seconds on any one clock.
"""
from collections import namedtuple

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
