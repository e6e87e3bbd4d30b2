"""The commands in flight: where a slow link's commands will take the robot.

No rospy here. A course (:class:`rbx1_nav.motion.course.Course`) records
every command it returns in an :class:`InFlight`; with a precise step
(:mod:`rbx1_nav.motion.precise`) it steers by :meth:`InFlight.predict`,
where the robot will be when its command lands, not by where an old pose
says it was. :class:`rbx1_nav.motion.stalls.Stalls` asks it which command
the robot ran at a given time.
"""
import bisect
from collections import deque

from rbx1_nav.common.geometry import arc_step
from rbx1_nav.motion.command import STOP

__all__ = ['InFlight']


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
        # From the command running at ``start``: the earlier ones ended before.
        first = max(bisect.bisect_right(self.times, start) - 1, 0)
        ends = self.times[first + 1:] + [now]
        for (sent, command), end in zip(self.sent[first:], ends):
            seconds = min(end, now) - max(sent, start)
            if seconds > 0.0:
                pose = arc_step(pose, command.linear * seconds,
                                command.angular * seconds)
        return pose
