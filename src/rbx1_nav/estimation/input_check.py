"""Screening of sensor readings before a filter uses them.

One check for ``pose_ekf.py`` (its odom, imu_data, vo and gps inputs, in
:class:`rbx1_nav.estimation.fusion.GyroOdomFusion`) and ``odom_ekf.py`` (its input
pose, in :class:`rbx1_nav.estimation.odom_ekf.PoseToOdometry`). :class:`InputCheck`
sorts out, per sensor, a reading that is

* ``zero stamp``: unstamped (a header stamp of 0);
* ``out of order``: stamped before the newest reading already taken from
  that sensor, or ``duplicate stamp``: stamped at the same time;
* ``not finite``: a NaN or infinite value or covariance entry;
* ``absurd``: a position beyond :data:`MAX_POSITION` or a covariance entry
  beyond :data:`MAX_VARIANCE`;
* ``negative variance``: a covariance with a negative diagonal entry;

or, as the callers find while unpacking a message, has a ``bad
orientation`` (a zero or non-finite quaternion, an IMU without one), is
``malformed``, or (a GPS fix) has a ``zero variance``, a ``stamp from
another clock`` or is a ``jump`` away from the estimate. Each rejection raises :class:`RejectedInput` and is counted;
:meth:`InputCheck.warning` turns it into at most one warning per sensor and
kind every :data:`WARN_PERIOD` seconds, saying how many were dropped since
the last one and (:func:`source_text`) the node that sent it.
:class:`ClockWatch` notices ROS time moving backwards, after which the
stamps start again (:meth:`InputCheck.new_clock`).

No rospy: stamps and times are float seconds.
"""
import math

import numpy as np

from rbx1_nav.common.throttle import Throttle

__all__ = ['InputCheck', 'RejectedInput', 'source_text',
           'MAX_POSITION', 'MAX_VARIANCE', 'WARN_PERIOD', 'ZERO_STAMP',
           'OUT_OF_ORDER', 'DUPLICATE', 'NOT_FINITE', 'ABSURD',
           'NEGATIVE_VARIANCE', 'BAD_ORIENTATION', 'MALFORMED',
           'ZERO_VARIANCE', 'OTHER_CLOCK', 'GPS_JUMP']

#: Positions farther than this from the origin (m) on either axis are
#: absurd. Ten times the largest coordinate a frame on Earth uses (UTM
#: northings reach 1e7 m, Earth-centred coordinates 6.4e6 m), so a GPS in
#: such a frame passes; at 1e8 m a float still resolves 15 nm, so the
#: filter's differences of two positions keep far below a millimetre.
MAX_POSITION = 1e8
#: Covariance entries above this (m^2, rad^2) are absurd: a standard
#: deviation of 1000 km. Above the usual "unknown" markers (1e6, 1e9),
#: far below a float's range, so a filter's sums and products of
#: covariances stay finite.
MAX_VARIANCE = 1e12
#: Seconds (ROS time) between two warnings of one sensor and kind.
WARN_PERIOD = 10.0

ZERO_STAMP = 'zero stamp'
OUT_OF_ORDER = 'out of order'
DUPLICATE = 'duplicate stamp'
NOT_FINITE = 'not finite'
ABSURD = 'absurd'
NEGATIVE_VARIANCE = 'negative variance'
BAD_ORIENTATION = 'bad orientation'
MALFORMED = 'malformed'
ZERO_VARIANCE = 'zero variance'
OTHER_CLOCK = 'stamp from another clock'
GPS_JUMP = 'jump'
#: Every kind of rejected reading.


class RejectedInput(ValueError):
    """A reading dropped by :class:`InputCheck`: its sensor, kind and what
    was wrong (``detail``, with the offending value)."""

    def __init__(self, sensor, kind, detail):
        super(RejectedInput, self).__init__('%s: %s' % (kind, detail))
        self.sensor, self.kind, self.detail = sensor, kind, detail


def source_text(sensor, topic, node=None):
    """Where a reading came from, for a warning: the sensor, its topic and the node
    that published it (None: unknown)."""
    return '%s on %s%s' % (sensor, topic, ' from %s' % node if node else '')


class InputCheck(object):
    """Screens readings per sensor; counts and throttles the rejections.

    :meth:`check` takes a reading or raises :class:`RejectedInput`; a taken
    reading's stamp becomes that sensor's newest, which later readings must
    pass. :meth:`warning` gives the text to log for a rejection, or None
    while that sensor and kind warned less than ``period`` seconds ago.
    """

    def __init__(self, period=WARN_PERIOD):
        self.period = float(period)
        self._newest = {}  # sensor -> stamp of the newest reading taken
        self._dropped = {}  # (sensor, kind) -> drops since the last warning
        self._rejected = {}  # sensor -> (drops in all, the last RejectedInput)
        self._throttle = Throttle(self.period)

    def newest(self, sensor):
        """Stamp of the newest reading taken from ``sensor``, or None."""
        return self._newest.get(sensor)

    def check(self, sensor, stamp, position=(), angles=(), covariance=None):
        """Take a reading of ``sensor`` stamped ``stamp`` (s), or raise.

        ``position``: coordinates in metres, finite and within
        :data:`MAX_POSITION`; ``angles``: values that need only be finite
        (a yaw in radians); ``covariance``: a square matrix, finite, no
        negative variance, no entry beyond :data:`MAX_VARIANCE`. The values
        are checked before the stamp, so a NaN reading is reported as such
        whatever its stamp. Raises :class:`RejectedInput` (counted) for a
        bad reading.
        """
        problem = (_value_problem(position, angles, covariance)
                   or self._stamp_problem(sensor, stamp))
        if problem is not None:
            raise self.reject(sensor, *problem)
        self._newest[sensor] = stamp

    def reject(self, sensor, kind, detail):
        """Count a dropped reading; the :class:`RejectedInput` to raise.

        For problems the caller finds itself (a bad quaternion).
        """
        key = (sensor, kind)
        self._dropped[key] = self._dropped.get(key, 0) + 1
        rejected = RejectedInput(sensor, kind, detail)
        self._rejected[sensor] = (self._rejected.get(sensor, (0,))[0] + 1, rejected)
        return rejected

    def dropped(self, sensor, kind):
        """Readings of ``sensor`` dropped as ``kind`` since the last warning."""
        return self._dropped.get((sensor, kind), 0)

    def rejected(self, sensor):
        """(readings of ``sensor`` dropped in all, the last :class:`RejectedInput`),
        or None before any."""
        return self._rejected.get(sensor)

    def warning(self, rejected, now, source=None):
        """The warning to log for ``rejected`` at ROS time ``now``, or None.

        One per sensor and kind every :attr:`period` seconds (sooner should
        time move backwards); it names ``source`` (the sensor and its topic;
        default the sensor), the kind, the offending value and how many
        readings of that kind were dropped since the previous warning.
        """
        key = (rejected.sensor, rejected.kind)
        if not self._throttle.ready(key, now):
            return None
        count = self._dropped.pop(key, 1)
        return ('dropped %s: %s: %s (%d such reading%s dropped since the last '
                'warning; at most one warning per %g s)' % (
                    source or rejected.sensor, rejected.kind, rejected.detail,
                    count, '' if count == 1 else 's', self.period))

    def new_clock(self):
        """ROS time restarted: forget every sensor's newest stamp."""
        self._newest.clear()

    def _stamp_problem(self, sensor, stamp):
        if stamp == 0.0:
            return ZERO_STAMP, 'the header stamp is 0 (unstamped)'
        if not math.isfinite(stamp):
            return NOT_FINITE, 'the header stamp is %r' % stamp
        newest = self._newest.get(sensor)
        if newest is None or stamp > newest:
            return None
        if stamp == newest:
            return DUPLICATE, ('stamp %.3f s is the same as the previous '
                               'reading\'s' % stamp)
        return OUT_OF_ORDER, ('stamp %.3f s is %.3f s older than the newest '
                              'reading taken, %.3f s' % (stamp, newest - stamp,
                                                         newest))


def _value_problem(position, angles, covariance):
    """``(kind, detail)`` for the first bad value, or None."""
    position = tuple(float(v) for v in position)
    if not all(math.isfinite(v) for v in position):
        return NOT_FINITE, ('position %s has a NaN or infinite component'
                            % _vector_text(position))
    for angle in angles:
        if not math.isfinite(angle):
            return NOT_FINITE, 'angle %r is NaN or infinite' % angle
    if position and max(abs(v) for v in position) > MAX_POSITION:
        return ABSURD, ('position %s is absurd: more than %g m from the '
                        'origin' % (_vector_text(position), MAX_POSITION))
    if covariance is None:
        return None
    # As Python floats: a few per reading, each reading checked.
    cov = np.array(covariance, dtype=float, ndmin=2)
    values = cov.ravel().tolist()
    for value in values:
        if not math.isfinite(value):
            return NOT_FINITE, 'covariance has a NaN or infinite entry (%r)' % value
    diag = cov.diagonal().tolist()
    if diag and min(diag) < 0.0:
        i = diag.index(min(diag))
        return NEGATIVE_VARIANCE, ('covariance has a negative variance %g '
                                   '(diagonal entry %d)' % (diag[i], i))
    largest = max(map(abs, values), default=0.0)
    if largest > MAX_VARIANCE:
        return ABSURD, ('covariance has an absurd entry %g (above %g)'
                        % (largest, MAX_VARIANCE))
    return None


def _vector_text(values):
    return '(%s)' % ', '.join('%g' % v for v in values)
