"""What a lockstep bag player publishes at each grant (no rospy here).

``rosbag play`` publishes a bag on the wall clock: a busy machine delays
some messages more than others, and a filter fed from it gives another
answer. Under lockstep (rbx1_nav.sim_time.lockstep) the player
(lockstep_play.py) is a member instead: granted T, it publishes every
message recorded up to T and asks for the time of the next one, so time
jumps from message to message and every run feeds the same messages at
the same simulated times. Times are integer nanoseconds of the bag's own
clock (its record times, as ``rosbag play --clock`` publishes).
"""

__all__ = ['Schedule']


class Schedule(object):
    """The bag's messages in record order, from ``start`` seconds after its
    first one: ``messages`` an iterable of (time ns, topic, message)."""

    def __init__(self, messages, start=0.0):
        self._messages = iter(messages)
        self.start = start
        self.first = None  # time (ns) of the bag's first message
        self.played = 0
        self._next = None
        self._advance()
        if self.first is not None:
            skip_until = self.first + int(round(start * 1e9))
            while self._next is not None and self._next[0] < skip_until:
                self._advance()

    def _advance(self):
        self._next = next(self._messages, None)
        if self._next is not None and self.first is None:
            self.first = self._next[0]

    @property
    def next_time(self):
        """Time (ns) of the next message to publish; None when none is left."""
        return None if self._next is None else self._next[0]

    def due(self, time):
        """[(topic, message)] of every message recorded up to ``time`` (ns)
        not published yet, in record order."""
        out = []
        while self._next is not None and self._next[0] <= time:
            out.append(self._next[1:])
            self._advance()
        self.played += len(out)
        return out
