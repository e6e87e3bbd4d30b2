"""One run of pose_ekf's filter: from its start to the next restart.

:class:`FilterRun` holds what a restart forgets: the filter
(:class:`rbx1_nav.estimation.ekf.PlanarEkf`, None until it starts), each
sensor's reference (what the sensor was last fused at) and the estimate's
stamp. It is what the two ways of stepping share:
:class:`rbx1_nav.estimation.relative_run.RelativeRun` (without GPS) and
:class:`rbx1_nav.estimation.gps_run.GpsRun` (robot_pose_ekf's GPS mode).
:class:`rbx1_nav.estimation.fusion.GyroOdomFusion` starts a new run on
each restart; a step that leaves the filter unusable raises
:class:`StepFailed` for it to do so. No rospy.
"""
import numpy as np

from rbx1_nav.estimation.sensors import SENSORS

__all__ = ['FilterRun', 'StepFailed']


class StepFailed(Exception):
    """A step left the filter unusable; ``cause`` (a ValueError or
    LinAlgError) says why. The fusion restarts."""

    def __init__(self, cause):
        super(StepFailed, self).__init__(cause)
        self.cause = cause


class FilterRun(object):
    """The filter's state between two restarts, over ``sensors`` (the
    :class:`rbx1_nav.estimation.sensors.SensorInputs` it reads).

    :attr:`ekf` is None until the run starts; :attr:`ref` maps each
    sensor to its reference; :attr:`stamp` is the estimate's, starting at
    ``stamp`` (the previous run's: the stamp never goes back across a
    restart, only on a new clock). After each :meth:`step`,
    :attr:`updated` says whether it fused news and :attr:`new_estimates`
    lists the estimates it made, oldest first. A subclass steps
    (``_step``) and says what a returning sensor's reference is
    (``_returned_ref``).
    """

    def __init__(self, sensors, stamp=None):
        self.sensors = sensors
        self.stamp = stamp
        self.ekf = None
        self.ref = dict.fromkeys(SENSORS)
        self.updated = False
        self.new_estimates = []

    @property
    def estimate(self):
        """``(stamp, (x, y, yaw), cov3)`` or None before the filter starts."""
        if self.ekf is None:
            return None
        return self.stamp, self.ekf.pose, self.ekf.cov.copy()

    def step(self, now, active):
        """Run the filter up to ``now`` on the ``active`` sensors; return
        log events ``(level, text)``. Raises :class:`StepFailed`."""
        self.updated, self.new_estimates = False, []
        events = self._step(now, active)
        if self.updated and not self.new_estimates:
            self.new_estimates.append(self.estimate)
        return events

    def _step(self, now, active):
        raise NotImplementedError

    def lost(self, name):
        """Sensor ``name`` timed out: leave it out until it is back."""
        self.ref[name] = None
        if self.ekf is not None:
            self.ekf.drop_anchor(name)

    def back(self, name):
        """Sensor ``name`` started or came back: it starts a new reference,
        so its jump while away (e.g. a restarted driver) is never fused."""
        self.ref[name] = self._returned_ref(name)
        if name in ('imu', 'vo') and self.ekf is not None:
            self.ekf.set_anchor(name)

    def _returned_ref(self, name):
        raise NotImplementedError

    def _advance(self, stamp):
        """Stamp the estimate ``stamp`` if that is newer; note progress
        (an estimate no newer than the last is not news)."""
        if self.stamp is None or stamp > self.stamp:
            self.stamp, self.updated = stamp, True

    def _check_finite(self):
        """ValueError unless the filter's mean and covariance are finite."""
        if not (np.all(np.isfinite(self.ekf.state))
                and np.all(np.isfinite(self.ekf.state_cov))):
            raise ValueError('the estimate is no longer finite')
