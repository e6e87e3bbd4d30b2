"""After a course's last step: wait for a still robot, then take its pose.

No rospy here. A command the link delayed can move the robot after the course read its final
pose, so the runner keeps commanding zero and feeds each pose to a :class:`Settle` until
odometry stood still ``settle_time`` s after the end and after every command sent before it was
acknowledged (:func:`delivered`: TCP can hold one back for seconds). Stamps count, not the
clock: a stale transform cannot be judged; the dropout hold (~link_grace) bounds that wait.
"""
import math
from collections import namedtuple

from rbx1_nav.common import params
from rbx1_nav.common.params import param
from rbx1_nav.transform_utils import normalize_angle

__all__ = ['GAVE_UP', 'delivered', 'LINEAR_EPS', 'ANGULAR_EPS', 'REPORT_M', 'REPORT_RAD',
           'SETTLE_PARAMS', 'STILL', 'Settle', 'WAITING', 'moved_text']

WAITING, STILL, GAVE_UP = 'waiting', 'still', 'gave up'

#: Still: within this of where a still spell began (rounding).
LINEAR_EPS = 2e-5  # m (0.02 mm)
ANGULAR_EPS = math.radians(0.002)  # rad
#: Motion after the course's end worth a warning.
REPORT_M = 1e-4  # m (0.1 mm)
REPORT_RAD = math.radians(0.01)  # rad

SETTLE_PARAMS = (
    param('settle_time', 0.6, params.number, 's',
          "after the last step, wait until odometry has stood still this "
          "long (longer than the robot's cmd_vel watchdog: a late command "
          "shows) and report that pose", **params.POSITIVE),
    param('settle_timeout', 5.0, params.number, 's',
          'give up waiting for a still robot (and say so) when odometry '
          'this long after the last step has not stood still', **params.POSITIVE),
)

Moved = namedtuple('Moved', 'distance yaw')
Moved.__doc__ = """Motion after the course ended: distance (m), yaw (rad, signed)."""


class Settle(object):
    """Wait for a still robot after the end: ``end`` (Pose2D), ``ended`` (s, the stamps' clock)."""

    def __init__(self, end, ended, settle_time, timeout):
        if not (settle_time > 0.0 and timeout > 0.0):
            raise ValueError('settle_time and timeout must be positive, got '
                             '%r and %r' % (settle_time, timeout))
        self.end, self.ended = end, float(ended)
        self.settle_time, self.timeout = float(settle_time), float(timeout)
        self.pose = end  # the pose fed last
        self._anchor = end  # where the current still spell began
        self._since = float(ended)  # its stamp, not before the end
        self.state = WAITING
        self.sent = True  # as update() was told last
        self.undelivered = None  # the stamp (s) commands were on their way last

    def update(self, pose, stamp, sent=True):
        """WAITING, STILL (the pose fed last is the settled one) or GAVE_UP (stamped ``timeout``
        s past the end without settling), after a new pose stamped ``stamp`` (s). ``sent`` is
        False while commands sent before the end may be on their way: no still spell begins."""
        self.pose, self.sent = pose, sent
        if not sent:
            self.undelivered = float(stamp)
        if not sent or not _same(pose, self._anchor):
            self._anchor = pose
            self._since = max(float(stamp), self.ended)
        if stamp - self._since >= self.settle_time - 1e-9:
            self.state = STILL
        elif stamp - self.ended >= self.timeout - 1e-9:
            self.state = GAVE_UP
        else:
            self.state = WAITING
        return self.state

    def moved(self):
        """How far the pose fed last is from the course's end pose."""
        return Moved(math.hypot(self.pose.x - self.end.x, self.pose.y - self.end.y),
                     normalize_angle(self.pose.yaw - self.end.yaw))


def delivered(unacknowledged, sent_since, message_bytes):
    """True when every command sent before the end reached the robot's host: ``unacknowledged``
    bytes (None: unknown) fit in the ``sent_since`` commands of ``message_bytes`` sent since."""
    return unacknowledged is None or unacknowledged <= sent_since * message_bytes


def _same(a, b):
    """True when pose ``a`` is within LINEAR_EPS / ANGULAR_EPS of ``b``."""
    return (math.hypot(a.x - b.x, a.y - b.y) <= LINEAR_EPS
            and abs(normalize_angle(a.yaw - b.yaw)) <= ANGULAR_EPS)


def moved_text(moved):
    """A warning's words for ``moved``, or None within REPORT_M / REPORT_RAD."""
    if moved.distance <= REPORT_M and abs(moved.yaw) <= REPORT_RAD:
        return None
    return ('the robot moved %.1f mm / %+.2f deg after the course ended '
            '(a late command?)' % (1000.0 * moved.distance, math.degrees(moved.yaw)))
