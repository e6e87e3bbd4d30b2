"""pose_ekf's filter without GPS: every sensor relative, stepped by messages.

:class:`RelativeRun` steps on each new message of the driving sensor
(odometry; without it visual odometry; without either the IMU),
predicting with the driver's increment and fusing the gyro's (and, while
odometry drives, visual odometry's) change since its last update. Its
output frame starts at the first odometry pose, known exactly. No rospy.
"""
import numpy as np

from rbx1_nav.estimation.ekf import (PlanarEkf, increment_cov, no_motion_cov,
                                     odom_increment)
from rbx1_nav.estimation.filter_run import FilterRun, StepFailed
from rbx1_nav.estimation.sensors import MOTION_SOURCES
from rbx1_nav.transform_utils import normalize_angle

__all__ = ['RelativeRun']


def _driver(active):
    """The sensor whose messages step the filter, or None."""
    for name in MOTION_SOURCES + ('imu',):
        if name in active:
            return name
    return None


class RelativeRun(FilterRun):
    """One run of the filter without GPS (see the module).

    A reference is the last reading fused: a sensor's news is the change
    since it, and a sensor that starts or returns takes its newest reading.
    """

    def __init__(self, sensors, stamp=None):
        super(RelativeRun, self).__init__(sensors, stamp)
        self._last_predict = None

    def _returned_ref(self, name):
        return self.sensors.latest[name]

    def _step(self, now, active):
        if self.ekf is None:
            self._last_predict = now
            return self._try_start(active)
        driver = _driver(active)
        if driver is None or not self._fresh(driver):
            return []
        fresh = [n for n in active if self._fresh(n)]
        try:
            with np.errstate(over='ignore', invalid='ignore'):
                self._fuse(now, driver, active, fresh)
        except (ValueError, np.linalg.LinAlgError) as err:
            raise StepFailed(err) from err
        self._advance_stamp(active)
        return []

    def _fresh(self, name):
        ref = self.ref[name]
        return ref is None or self.sensors.latest[name].seq != ref.seq

    def _try_start(self, active):
        """Start at the first odometry (else visual odometry, else IMU)."""
        latest = self.sensors.latest
        source = next((n for n in MOTION_SOURCES if self.sensors.used(n)),
                      None)
        if source is not None:
            if source not in active:
                return []
            # The output frame starts at this pose: known exactly, whatever
            # the sensor's own uncertainty of it.
            self.ekf = PlanarEkf(latest[source].value, np.zeros((3, 3)),
                                 anchors=())
            where = 'the first %s pose' % (
                'odometry' if source == 'odom' else 'visual odometry')
        else:
            if 'imu' not in active:
                return []
            self.ekf = PlanarEkf((0.0, 0.0, 0.0), np.zeros((3, 3)), anchors=())
            where = 'the origin (no odometry used)'
        for name in active:
            self.ref[name] = latest[name]
            if name == 'imu' or (name == 'vo' and source != 'vo'):
                self.ekf.set_anchor(name)
        self._advance_stamp(active)
        x, y, yaw = self.ekf.pose
        return [('info', 'filter started at %s: x=%.3f y=%.3f yaw=%.3f'
                 % (where, x, y, yaw))]

    def _fuse(self, now, driver, active, fresh):
        """Predict to ``now`` with the driver; fuse the others' news."""
        self._predict(driver, max(now - self._last_predict, 0.0))
        self._last_predict = now
        self._check_finite()
        for name in ('imu', 'vo'):
            relative = name in active and (name == 'imu' or name != driver)
            if not relative:
                self.ekf.drop_anchor(name)
                continue
            reading = self.sensors.latest[name]
            if not self.ekf.has_anchor(name) or self.ref[name] is None:
                # A new anchor: measure from here on (e.g. visual odometry
                # after odometry came back and took over the prediction).
                self.ref[name] = reading
                self.ekf.set_anchor(name)
                continue
            if name not in fresh:
                continue
            if not reading.measured:
                self.ekf.set_anchor(name)  # nothing measured: re-anchor
            elif name == 'imu':
                self.ekf.update_yaw_increment(
                    normalize_angle(reading.value - self.ref[name].value),
                    reading.cov, name)
            else:
                self.ekf.update_pose_increment(
                    odom_increment(self.ref[name].value, reading.value),
                    reading.cov, name, reading.measured)
            self.ref[name] = reading
            self._check_finite()

    def _predict(self, driver, dt):
        """Predict with the driver's increment, or 'no motion' without one."""
        if driver in MOTION_SOURCES:
            reading, ref = self.sensors.latest[driver], self.ref[driver]
            increment = odom_increment(ref.value, reading.value)
            # An unmeasured component grows over the time the increment
            # spans (its two stamps), not over the filter's step: when
            # the step falls between two messages must not matter.
            self.ekf.predict(increment, increment_cov(
                increment, reading, reading.stamp - ref.stamp))
            self.ref[driver] = reading
        else:
            self.ekf.predict((0.0, 0.0, 0.0), no_motion_cov(dt))

    def _advance_stamp(self, active):
        """Stamp the estimate with the newest fused message."""
        self._advance(max(self.sensors.latest[n].stamp for n in active))
