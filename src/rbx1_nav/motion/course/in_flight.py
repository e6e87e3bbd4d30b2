"""The commands in flight: where a slow link's commands will take the robot.

No rospy here. A Course records its commands here; precise mode steers by :meth:`InFlight.predict`.
"""
import bisect
from collections import deque

from rbx1_nav.common.geometry import arc_step
from rbx1_nav.motion.course.command import STOP

__all__ = ['InFlight']


class InFlight(object):
    """The commands sent. A pose read over a slow link is ``age`` s old and a command sent now
    lands ``delay`` later: :meth:`predict` adds the arcs of those sent since ``stamp - delay``.
    ``delay`` is the link's the other way: the smallest age of the last ``memory`` readings (a
    reading that waited for the control tick is older)."""

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
        """The command running at ``when`` (s): the last sent by ``when - delay``, else STOP."""
        ran = bisect.bisect_right(self.times, when - self.delay)
        return self.sent[ran - 1][1] if ran else STOP

    def predict(self, pose, now, age):
        """``pose``, read at ``now`` and ``age`` s old, moved on by the commands in flight."""
        start = now - age - self.delay
        # From the command running at ``start``: the earlier ones ended before.
        first = max(bisect.bisect_right(self.times, start) - 1, 0)
        ends = self.times[first + 1:] + [now]
        for (sent, command), end in zip(self.sent[first:], ends):
            seconds = min(end, now) - max(sent, start)
            if seconds > 0.0:
                pose = arc_step(pose, command.linear * seconds, command.angular * seconds)
        return pose
