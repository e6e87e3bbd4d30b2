"""pose_ekf's filter with ``gps_used``: robot_pose_ekf's GPS mode.

:class:`GpsRun` starts at a GPS fix with the IMU's heading (its output
frame is the GPS frame), then steps as robot_pose_ekf does: at the oldest
of the active sensors' newest stamps, read off the stamps so the answer
does not depend on when the node's timer fires. It takes the IMU's yaw as
absolute while GPS is active and the fixes on x, y only (z is ignored).
With ``gps_frame_rotation`` it also estimates the rotation between the
GPS frame and the IMU's heading. No rospy.
"""
import bisect
import math

import numpy as np

from rbx1_nav.estimation.ekf import (NO_ODOM_VARIANCE_RATE, PlanarEkf,
                                     increment_cov, no_motion_cov,
                                     odom_increment)
from rbx1_nav.estimation.filter_run import FilterRun, StepFailed
from rbx1_nav.estimation.input_check import GPS_JUMP
from rbx1_nav.estimation.sensors import SENSORS
from rbx1_nav.transform_utils import normalize_angle

__all__ = ['GpsRun', 'GPS_GATE_SIGMAS']

#: A fix farther than this many standard deviations (of the fix and the
#: estimate together) from the prediction is dropped as a jump, not fused.
GPS_GATE_SIGMAS = 10.0
#: At most this many seconds of filter steps are caught up at once (after
#: a stall, the first step spans the rest).
MAX_CATCH_UP = 10.0
#: A stamp this fraction of a tick before it counts as on it
#: (floating-point sums of 1/freq fall just short).
TICK_EPSILON = 1e-3


class GpsRun(FilterRun):
    """One run of the filter in robot_pose_ekf's GPS mode (see the module).

    ``freq`` is the filter rate (Hz); with ``gps_kalman`` each fix is
    fused once with the Kalman gain (instead of robot_pose_ekf's pull at
    every step); ``gps_frame_rotation`` (a prior standard deviation in
    rad, or None) makes the rotation between the GPS frame and the IMU's
    heading a state, with prior ``N(0, gps_frame_rotation**2)``, that the
    fixes refine as the robot moves. A reference is a sensor's value at the
    last filter time: a sensor that starts or returns takes one at the next.
    """

    def __init__(self, sensors, stamp, freq, gps_kalman, gps_frame_rotation):
        super(GpsRun, self).__init__(sensors, stamp)
        self.freq = freq
        self.gps_kalman = gps_kalman
        self.gps_frame_rotation = gps_frame_rotation
        self._time = None  # the filter's time (s)
        self._tick = 0  # the next tick (s * freq) to read
        self._was_active = set()  # sensors active at that time
        self._gps_fused = None  # stamp of the last fix used

    def _returned_ref(self, name):
        return None

    def _step(self, now, active):
        """The filter starts when both the IMU and GPS are active, at the
        fix and the IMU's heading (with ``gps_frame_rotation``, as the
        prior of the heading). Then it steps at every filter time since its
        last step (:meth:`_step_times`), where every sensor is read by
        interpolation: odometry (and visual odometry) increments since the
        last step, the IMU's yaw as absolute while GPS is active (relative
        otherwise), and each new fix on x, y (the first after GPS starts or
        returns is skipped).
        """
        if self.ekf is None:
            return self._start(active)
        if not active:
            return []
        latest = self.sensors.latest
        times = self._step_times(min([now] + [latest[n].stamp for n in active]),
                                 active)
        if not times:
            return []
        # With gps_kalman, step at each new fix's own stamp on the way
        # (not past the last filter time: later ones are never older).
        if self.gps_kalman and 'gps' in active:
            times = sorted(set(times + [
                r.stamp for r in self.sensors.history['gps']
                if self._time < r.stamp <= times[-1]]))
        events = []
        try:
            with np.errstate(over='ignore', invalid='ignore'):
                for step_time in times:
                    events += self._fuse_at(step_time, active)
                    self._time = step_time
                    self._was_active = set(active)
                    self.new_estimates.append(
                        (step_time, self.ekf.pose, self.ekf.cov.copy()))
        except (ValueError, np.linalg.LinAlgError) as err:
            raise StepFailed(err) from err
        self._advance(times[-1])
        return events

    def _step_times(self, t, active):
        """robot_pose_ekf's filter times after the last step, up to ``t``.

        robot_pose_ekf steps, ``freq`` times a second, at the oldest of its
        sensors' newest stamps. Here that is read off the stamps, not off
        when the node's timer fires or messages arrive: at each multiple
        of ``1/freq`` s up to ``t``, the oldest of the sensors' newest
        stamps not after it (the newest :data:`MAX_CATCH_UP` s of them).
        """
        stamps = {n: [r.stamp for r in self.sensors.history[n]]
                  for n in active}
        times = set()
        last = int(math.floor(t * self.freq + TICK_EPSILON))
        for k in range(max(self._tick, last - int(MAX_CATCH_UP * self.freq)),
                       last + 1):
            tick = (k + TICK_EPSILON) / self.freq
            newest = [own[bisect.bisect_right(own, tick) - 1]
                      for own in stamps.values()
                      if own and own[0] <= tick]
            if len(newest) == len(stamps) and min(newest) > self._time:
                times.add(min(newest))
        self._tick = last + 1
        return sorted(times)

    def _start(self, active):
        if 'imu' not in active or 'gps' not in active:
            return []
        fix, imu = self.sensors.latest['gps'], self.sensors.latest['imu']
        if len(fix.measured) < 2 or not imu.measured:
            return []  # noted once when it came in
        t = fix.stamp
        yaw = self.sensors.value_at('imu', t)
        cov = np.zeros((3, 3))
        cov[0:2, 0:2], cov[2, 2] = fix.cov, imu.cov
        self.ekf = PlanarEkf(fix.value + (yaw,), cov, anchors=())
        if self.gps_frame_rotation is not None:
            self.ekf.add_rotation(self.gps_frame_rotation ** 2)
        self._time, self._gps_fused = t, t  # this fix is used up
        self._was_active = set(active)
        for name in active:
            self.ref[name] = self.sensors.value_at(name, t)
        self._advance(t)
        heading = 'the IMU heading'
        if self.gps_frame_rotation is not None:
            heading += ' give or take %.0f deg (gps_frame_rotation)' % (
                math.degrees(self.gps_frame_rotation))
        return [('info', 'filter started at the GPS fix and %s (gps_used: '
                 'the output frame is the GPS frame): x=%.3f y=%.3f yaw=%.3f'
                 % ((heading,) + self.ekf.pose))]

    def _fuse_at(self, t, active):
        """Predict to filter time ``t`` and fuse every active sensor there."""
        sensors = self.sensors
        dt = t - self._time
        events = []
        now = {n: sensors.value_at(n, t) for n in active}
        ref = {n: self.ref[n] if n in self._was_active else None
               for n in SENSORS}
        if 'odom' in active and ref['odom'] is not None:
            increment = odom_increment(ref['odom'], now['odom'])
            self.ekf.predict(increment, increment_cov(
                increment, sensors.reading_at('odom', t), dt,
                scale=dt / sensors.period('odom', dt, t)))
        else:
            self.ekf.predict((0.0, 0.0, 0.0), no_motion_cov(dt))
        self._check_finite()
        imu, vo = sensors.reading_at('imu', t), sensors.reading_at('vo', t)
        if 'imu' in active and imu.measured and (
                'gps' in active or self.ekf.rotation is not None):
            self.ekf.update_yaw(now['imu'], imu.cov)
        elif ('imu' in active and imu.measured and ref['imu'] is not None
              and self.ekf.has_anchor('imu')):
            self.ekf.update_yaw_increment(
                normalize_angle(now['imu'] - ref['imu']), imu.cov)
        if 'vo' in active and ref['vo'] is not None and self.ekf.has_anchor(
                'vo'):
            self.ekf.update_pose_increment(
                odom_increment(ref['vo'], now['vo']),
                vo.cov * (dt / sensors.period('vo', dt, t)), 'vo', vo.measured)
        for name in ('imu', 'vo'):
            (self.ekf.set_anchor if name in active
             else self.ekf.drop_anchor)(name)
        self._check_finite()
        if 'gps' in active:
            events += self._fuse_fix(t, ref['gps'] is None)
        else:
            self._gps_fused = None
        self.ref.update(now)
        return events

    def _fuse_fix(self, t, first):
        """Fuse the GPS position at ``t``; the first step after GPS starts
        or returns only reads it.

        As robot_pose_ekf: at every step, the fix (read at ``t``) pulls the
        position by the weight its covariance has against odometry's. With
        ``gps_kalman``: each fix once, with the Kalman gain.
        """
        sensors = self.sensors
        if first:
            self._gps_fused = sensors.reading_at('gps', t).stamp
            return []
        if self.gps_kalman:
            fix = next(r for r in reversed(sensors.history['gps'])
                       if r.stamp <= t)
            if fix.stamp <= self._gps_fused:
                return []
            self._gps_fused, position = fix.stamp, fix.value
        else:
            fix, position = sensors.reading_at('gps', t), sensors.value_at('gps', t)
        if not fix.measured:
            return []
        distance = self.ekf.position_distance(position, fix.cov,
                                              fix.measured)
        if distance > GPS_GATE_SIGMAS:
            return self._jump_warning(t, position, distance)
        if self.gps_kalman:
            self.ekf.update_position(position, fix.cov, fix.measured)
        else:
            odom = sensors.reading_at('odom', t)
            motion = (np.diag(odom.cov)[0:2] if 'odom' in self._was_active
                      else NO_ODOM_VARIANCE_RATE[0:2])
            self.ekf.blend_position(position, fix.cov,
                                    motion / (motion + np.diag(fix.cov)),
                                    fix.measured)
        self._check_finite()
        return []

    def _jump_warning(self, t, position, distance):
        """The fix at ``t`` is ``distance`` sd from the estimate: count it
        as rejected; the warning event, when it is time for one."""
        inputs = self.sensors.inputs
        x, y, _ = self.ekf.pose
        text = inputs.warning(inputs.reject(
            'gps', GPS_JUMP, 'fix (%.2f, %.2f) is %.1f m (%.0f sd) from '
            'the estimate (%.2f, %.2f): not fused' % (
                position + (math.hypot(position[0] - x, position[1] - y),
                            distance, x, y))), t,
            'gps on %s' % self.sensors.topics.get('gps', 'gps'))
        return [('warn', text)] if text else []
