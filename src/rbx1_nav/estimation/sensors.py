"""The sensor bookkeeping of pose_ekf: what came in from each sensor.

:class:`SensorInputs` takes each sensor's messages as plain values
(``add_odom``, ``add_imu``, ``add_vo``, ``add_gps``), checks them
(:class:`rbx1_nav.estimation.input_check.InputCheck`: unstamped, out of order, NaN or
absurd readings, negative variances; for GPS also a zero variance or a
stamp from another clock), splits off the components a driver marks "not
measured" (:func:`unmeasured_components`, said once per sensor at info
level), and keeps the latest readings and a short history of each sensor
to read it at any time between them (:meth:`SensorInputs.value_at`).
:class:`SensorWatch` tells whether a sensor is active (seen within
``sensor_timeout``), lost or back; :meth:`SensorInputs.silent_sensors`
names the used sensors that never sent anything after start-up. What the
filter does with the readings is :mod:`rbx1_nav.estimation.fusion` (and
the runs it starts). No rospy.
"""
import collections

import numpy as np

from rbx1_nav.estimation.input_check import OTHER_CLOCK, ZERO_VARIANCE, InputCheck
from rbx1_nav.estimation.ekf import floored
from rbx1_nav.transform_utils import normalize_angle

__all__ = ['SensorInputs', 'SensorWatch', 'Reading', 'unmeasured_components',
           'SENSORS', 'MOTION_SOURCES', 'UNMEASURED_VARIANCE',
           'MAX_STAMP_SKEW', 'HISTORY']

#: A variance at or above this (m^2, rad^2), -1 or infinity is a driver's
#: "do not use this component" (1e6 in robot_pose_ekf's users, 1e10 and
#: 1e308 in Kobuki's, DBL_MAX in others): the component is left unmeasured,
#: never fused as a number (a sd of 316 m or 316 rad means nothing anyway).
UNMEASURED_VARIANCE = 1e5
#: A GPS stamp farther than this from ROS time (s) is from another clock.
MAX_STAMP_SKEW = 10.0
#: Readings kept per sensor, to read each at the filter's time (GPS mode).
HISTORY = 100
#: How many readings a sensor's mean period is taken over.
PERIOD_READINGS = 20
_AXES = {'odom': ('x', 'y', 'yaw'), 'vo': ('x', 'y', 'yaw'), 'imu': ('yaw',),
         'gps': ('x', 'y')}


def unmeasured_components(cov):
    """``(cleaned, mask)`` for a sensor covariance.

    ``mask[i]`` is True where variance ``i`` says "not measured" (at least
    :data:`UNMEASURED_VARIANCE`, exactly -1, or +infinity); ``cleaned`` is
    ``cov`` with those rows and columns zeroed, ready for the input check.
    """
    cleaned = np.array(cov, dtype=float, ndmin=2)  # a copy
    # Compared as Python floats: a NaN variance is "measured" (and refused
    # later), without numpy's warning. A few floats per message, so no
    # numpy call is spared: this runs for every reading.
    flags = [v >= UNMEASURED_VARIANCE or v == -1.0 for v in cleaned.diagonal().tolist()]
    mask = np.array(flags, dtype=bool)
    if any(flags):
        cleaned[mask, :] = 0.0
        cleaned[:, mask] = 0.0
    return cleaned, mask


class SensorWatch(object):
    """Tracks whether a sensor is fresh: seen within ``timeout`` seconds."""

    def __init__(self, name, timeout):
        self.name = name
        self.timeout = float(timeout)
        self.last_seen = None
        self.last_stamp = None
        self.active = False
        self.ever_active = False
        self.lost_at = None

    def seen(self, now, stamp=None):
        """Record a message received at time ``now`` (seconds)."""
        self.last_seen = now
        self.last_stamp = stamp

    def check(self, now):
        """Update :attr:`active`; return 'started', 'back', 'lost' or None."""
        fresh = (self.last_seen is not None
                 and now - self.last_seen <= self.timeout)
        if fresh and not self.active:
            self.active = True
            self.lost_at = None
            event = 'back' if self.ever_active else 'started'
            self.ever_active = True
            return event
        if self.active and not fresh:
            self.active = False
            self.lost_at = now
            return 'lost'
        return None

    def describe(self, now):
        """'active', 'waiting (never received)' or 'dropped (...)'."""
        if self.active:
            return 'active'
        if self.last_seen is None:
            return 'waiting (no message received yet)'
        return 'dropped (no message for %.2f s)' % (now - self.last_seen)


class Reading(object):
    """One validated sensor message: its stamp, value and covariance."""

    def __init__(self, stamp, value, cov, seq, unmeasured):
        self.stamp, self.value, self.cov, self.seq = stamp, value, cov, seq
        #: components whose variance said "not measured"
        self.unmeasured = unmeasured

    @property
    def measured(self):
        """Indices of the measured components."""
        return [i for i, m in enumerate(self.unmeasured) if not m]


#: Every sensor the filter knows, in robot_pose_ekf's order.
SENSORS = ('odom', 'imu', 'vo', 'gps')
#: Sensors whose motion can drive the prediction, by preference.
MOTION_SOURCES = ('odom', 'vo')


class SensorInputs(object):
    """Each used sensor's readings, checked, and whether it is active.

    :attr:`watches` maps each sensor to its :class:`SensorWatch`;
    :attr:`latest` to its newest :class:`Reading` and :attr:`history` to
    the last :data:`HISTORY` of them (what the filter's runs read).
    :attr:`inputs` counts the rejected readings, :attr:`started_at` is
    start-up. :meth:`forget_readings` empties all but the rejection counts
    (a restart); notes for the log (the "not measured" components) collect
    in ``_notes``.
    """

    def __init__(self, odom_used, imu_used, vo_used, gps_used,
                 sensor_timeout, topics=None):
        self.odom_used, self.imu_used = bool(odom_used), bool(imu_used)
        self.vo_used, self.gps_used = bool(vo_used), bool(gps_used)
        self.sensor_timeout = sensor_timeout
        self._seq = 0
        self.started_at = None  # time of the first step: start-up
        self._silent_reported = set()
        self.inputs = InputCheck()
        #: sensor -> topic, for the texts
        self.topics = dict(topics or {})
        self._noted = set()  # (sensor, unmeasured mask) already noted
        self._notes = []  # notes for the next step's events
        self.forget_readings()

    def forget_readings(self):
        """Forget every reading and whether each sensor was ever active."""
        self.watches = {name: SensorWatch(name, self.sensor_timeout)
                        for name in SENSORS}
        self.latest = dict.fromkeys(SENSORS)
        self.history = {name: collections.deque(maxlen=HISTORY)
                        for name in SENSORS}

    # -- input ----------------------------------------------------------------
    def add_odom(self, now, stamp, pose, cov3):
        """An odometry pose ``(x, y, yaw)`` stamped ``stamp`` with its 3x3
        covariance, received at ``now``.

        Raises RejectedInput (a ValueError) and keeps nothing for a zero,
        repeated or older stamp than the last odometry's, a NaN pose or
        covariance, a negative variance, a position beyond
        :data:`MAX_POSITION` or a covariance entry beyond
        :data:`MAX_VARIANCE`.
        """
        self._add_pose('odom', now, stamp, pose, cov3)

    def add_vo(self, now, stamp, pose, cov3):
        """A visual odometry pose ``(x, y, yaw)`` with its 3x3 covariance.

        Checked like :meth:`add_odom`; fused through its own increments.
        """
        self._add_pose('vo', now, stamp, pose, cov3)

    def add_imu(self, now, stamp, yaw, variance):
        """An IMU yaw (radians) with its variance; checked like
        :meth:`add_odom`."""
        cov, mask = self._screen('imu', [[variance]])
        if self._taken('imu', stamp, angles=(yaw,), covariance=cov):
            self._add('imu', now, stamp, normalize_angle(yaw),
                      floored(cov)[0, 0], mask)

    def add_gps(self, now, stamp, position, cov2):
        """A GPS fix ``(x, y)`` in metres with its 2x2 covariance; checked
        like :meth:`add_odom`, and dropped too for a zero variance (a GPS
        never knows its position exactly) or a stamp more than
        :data:`MAX_STAMP_SKEW` from ``now`` (another clock)."""
        x, y = (float(v) for v in position)
        cov, mask = self._screen('gps', cov2)
        if not self.used('gps'):
            return
        measured = np.diag(cov)[~mask]
        if np.any(measured == 0.0):
            raise self.inputs.reject('gps', ZERO_VARIANCE, (
                'the fix\'s covariance has a zero variance: no GPS knows '
                'its position exactly (set its real covariance)'))
        if abs(stamp - now) > MAX_STAMP_SKEW:
            raise self.inputs.reject('gps', OTHER_CLOCK, (
                'stamp %.3f s is %.1f s from ROS time %.3f s: the GPS stamps '
                'with another clock (stamp with ROS time)' % (
                    stamp, stamp - now, now)))
        if self._taken('gps', stamp, position=(x, y), covariance=cov):
            self._add('gps', now, stamp, (x, y), floored(cov), mask)

    def _add_pose(self, name, now, stamp, pose, cov3):
        x, y, yaw = (float(v) for v in pose)
        cov, mask = self._screen(name, cov3)
        if self._taken(name, stamp, position=(x, y), angles=(yaw,),
                       covariance=cov):
            self._add(name, now, stamp, (x, y, normalize_angle(yaw)),
                      floored(cov), mask)

    def _screen(self, name, cov):
        """Split off the unmeasured components of a sensor covariance;
        note (once per sensor and set of components) which they are."""
        cleaned, mask = unmeasured_components(cov)
        key = (name, tuple(mask))
        if mask.any() and self.used(name) and key not in self._noted:
            self._noted.add(key)
            axes = [a for a, m in zip(_AXES[name], mask) if m]
            values = ['%g' % v for v, m in zip(np.diag(
                np.array(cov, dtype=float, ndmin=2)), mask) if m]
            self._notes.append(('info', '%s on %s: variance %s of %s means '
                                '"not measured" (at least %g, -1 or inf): '
                                '%s not fused from it' % (
                                    name, self.topics.get(name, name),
                                    ', '.join(values), ', '.join(axes),
                                    UNMEASURED_VARIANCE, ', '.join(axes))))
        return cleaned, mask

    def _taken(self, name, stamp, **values):
        """False for an unused sensor; raises RejectedInput for a bad
        reading (:meth:`InputCheck.check`)."""
        if not self.used(name):
            return False
        self.inputs.check(name, stamp, **values)
        return True

    def _add(self, name, now, stamp, value, cov, unmeasured):
        self._seq += 1
        reading = Reading(stamp, value, cov, self._seq, unmeasured)
        self.latest[name] = reading
        self.history[name].append(reading)
        self.watches[name].seen(now, stamp)

    def used(self, name):
        """Whether sensor ``name`` is used (its ``<name>_used`` flag)."""
        return getattr(self, name + '_used')

    def used_sensors(self):
        return [n for n in SENSORS if self.used(n)]

    def value_at(self, name, t):
        """Sensor ``name``'s value at time ``t``, interpolated between the
        two readings around it (the nearest one outside them)."""
        history = self.history[name]
        after = None
        for before in reversed(history):
            if before.stamp <= t:
                break
            after = before
        else:
            return history[0].value
        if after is None or before.stamp == t:
            return before.value
        f = (t - before.stamp) / (after.stamp - before.stamp)
        b = np.atleast_1d(before.value)
        d = np.atleast_1d(after.value) - b
        if name != 'gps':  # the last component is a yaw
            d[-1] = normalize_angle(d[-1])
        value = [float(v) for v in b + f * d]
        if name != 'gps':
            value[-1] = normalize_angle(value[-1])
        return value[0] if name == 'imu' else tuple(value)

    def reading_at(self, name, t):
        """Sensor ``name``'s last reading stamped up to ``t`` (else its
        oldest kept; None before any)."""
        history = self.history[name]
        for reading in reversed(history):
            if reading.stamp <= t:
                return reading
        return history[0] if history else None

    def period(self, name, default, until):
        """Mean interval (s) of sensor ``name``'s last :data:`PERIOD_READINGS`
        readings stamped up to ``until`` (not of those that happen to have
        arrived since)."""
        stamps = [r.stamp for r in self.history[name]
                  if r.stamp <= until][-PERIOD_READINGS:]
        if len(stamps) < 2:
            return max(default, 1e-6)
        return max((stamps[-1] - stamps[0]) / (len(stamps) - 1), 1e-6)

    # -- start-up checks and status -------------------------------------------
    def start(self, now):
        """Mark start-up at ``now`` (the first :meth:`step` does otherwise):
        a node calls it before it connects its topics, so the time that
        takes counts towards ``sensor_timeout``."""
        if self.started_at is None:
            self.started_at = now

    def silent_sensors(self, now):
        """Used sensors with no message ``sensor_timeout`` after start-up.

        Start-up is :meth:`start` or the first :meth:`step`. Each sensor is returned once,
        at the first call past that time; the caller warns about it.
        """
        if self.started_at is None or now - self.started_at < self.sensor_timeout:
            return []
        silent = [n for n in self.used_sensors() if n not in self._silent_reported
                  and self.watches[n].last_seen is None]
        self._silent_reported.update(silent)
        return silent
