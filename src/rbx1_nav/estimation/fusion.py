"""The fusion of pose_ekf: when the filter starts, steps and restarts,
and which sensor does what in it.

:class:`GyroOdomFusion` takes the sensors' readings through
:class:`rbx1_nav.estimation.sensors.SensorInputs` and runs the filter of
:mod:`rbx1_nav.estimation.ekf` on them: without GPS it steps on each new
odometry message (without odometry, visual odometry; without either, the
IMU), predicting with the driving sensor's increment and fusing the
gyro's (and visual odometry's) change since its last update; with
``gps_used`` it steps as robot_pose_ekf does, at the oldest of the active
sensors' newest stamps (read off the stamps, so the answer does not depend
on when the node's timer fires), and can estimate the rotation between
the GPS frame and the IMU's heading (``gps_frame_rotation``). It applies the sensor timeouts, restarts itself
should its estimate stop being finite or ROS time move backwards, and
gives its state as text through :mod:`rbx1_nav.estimation.status`. No rospy.
"""
import bisect
import math

import numpy as np

from rbx1_nav.estimation.input_check import GPS_JUMP
from rbx1_nav.common.ros_time import ClockWatch
from rbx1_nav.estimation.ekf import (NO_ODOM_VARIANCE_RATE, PlanarEkf,
                                     increment_cov, no_motion_cov,
                                     odom_increment)
from rbx1_nav.estimation.sensors import MOTION_SOURCES, SENSORS, SensorInputs
from rbx1_nav.estimation.status import state_text, status_text
from rbx1_nav.transform_utils import normalize_angle

__all__ = ['GyroOdomFusion', 'GPS_GATE_SIGMAS']

#: GPS in robot_pose_ekf's mode: a fix farther than this many standard
#: deviations (of the fix and the estimate together) from the prediction is
#: dropped as a jump, not fused.
GPS_GATE_SIGMAS = 10.0
#: GPS mode: at most this many seconds of filter steps are caught up at
#: once (after a stall, the first step spans the rest).
MAX_CATCH_UP = 10.0
#: GPS mode: a stamp this fraction of a tick before it counts as on it
#: (floating-point sums of 1/freq fall just short).
TICK_EPSILON = 1e-3
#: Every used sensor silent for this many sensor timeouts: all are dropped
#: (before that, a sensor is dropped when it is silent while others talk).
ALL_SILENT_TIMEOUTS = 5.0


class GyroOdomFusion(SensorInputs):
    """The whole robot_pose_ekf-like fusion, fed plain values.

    Sensors: wheel odometry (``odom``), a gyro's yaw (``imu``), visual
    odometry (``vo``) and GPS (``gps``). The first active of odometry and
    visual odometry drives the prediction with its increments; the gyro and
    (while odometry drives) visual odometry are fused as relative
    measurements of the motion since their previous update. Without GPS
    the output frame starts at the first odometry pose, known exactly. With
    ``gps_used`` the filter works as robot_pose_ekf does
    (:meth:`_step_gps_mode`): it starts at a fix with the IMU's heading,
    takes the IMU's yaw as absolute while GPS is active and the fixes on
    x, y only (z is ignored). With ``gps_frame_rotation`` (a prior standard
    deviation in rad) the IMU's heading is not taken as true in the GPS
    frame: the rotation between the two is a state, with prior ``N(0,
    gps_frame_rotation**2)``, that the fixes refine as the robot moves
    (each fix fused once with the Kalman gain, as with ``gps_kalman``).

    Call :meth:`add_odom` / :meth:`add_imu` / :meth:`add_vo` /
    :meth:`add_gps` per message (their checks and timeouts are
    :class:`rbx1_nav.estimation.sensors.SensorInputs`) and :meth:`step` at the filter rate.
    :meth:`step` returns log events ``(level, text)``; after it,
    :attr:`estimate` is ``(stamp, pose, cov3)`` or None, and :attr:`updated`
    says whether this step fused new data. Should a step ever leave a
    non-finite estimate, the filter :meth:`restart` s (with a warning event)
    instead of reporting it.

    Every reading passes :attr:`inputs` (an
    :class:`rbx1_nav.estimation.input_check.InputCheck`): an unstamped, out-of-order,
    repeated, NaN or absurd reading raises
    :class:`rbx1_nav.estimation.input_check.RejectedInput` and is not kept, so the
    estimate's stamp never goes back. Call :meth:`check_clock` with the
    current ROS time before each reading and step: should it move
    backwards, the filter restarts from the next readings on the new clock.
    """

    def __init__(self, odom_used=True, imu_used=True, sensor_timeout=1.0,
                 vo_used=False, gps_used=False, topics=None,
                 gps_kalman=False, gps_frame_rotation=None, freq=30.0):
        if not (odom_used or imu_used or vo_used):
            raise ValueError('at least one of odom_used, imu_used and vo_used '
                             'is needed (GPS alone gives no heading)')
        super(GyroOdomFusion, self).__init__(odom_used, imu_used, vo_used,
                                             gps_used, sensor_timeout, topics)
        if gps_frame_rotation is not None and not gps_frame_rotation > 0.0:
            raise ValueError('gps_frame_rotation (the prior standard '
                             'deviation of the rotation) must be above 0, '
                             'got %r' % (gps_frame_rotation,))
        self.gps_frame_rotation = gps_frame_rotation
        self.gps_kalman = bool(gps_kalman) or gps_frame_rotation is not None
        self.freq = float(freq)
        self.restarts = 0
        self._clock = ClockWatch()
        self.stamp = None
        self.restart()

    def restart(self, new_clock=False):
        """Forget the estimate and every reading received so far.

        The filter starts again like a new one: from the next odometry
        message (without odometry, from the next visual odometry or IMU
        message). Its readings and its estimate must still be newer than
        the last ones, unless ``new_clock`` (ROS time moved backwards):
        then the next readings are taken whatever their stamps.
        """
        self.forget_readings()
        self._ref = dict.fromkeys(SENSORS)
        self._time = None  # GPS mode: the filter's time (s)
        self._tick = 0  # GPS mode: the next tick (s * freq) to read
        self._was_active = set()  # GPS mode: sensors active at that time
        self._gps_fused = None  # GPS mode: stamp of the last fix used
        self._last_predict = None
        self.ekf = None
        self.updated = False
        self.new_estimates = []
        if new_clock:
            self.stamp = None
            self.inputs.new_clock()

    def check_clock(self, now):
        """Seconds ROS time moved back since the previous call, or 0.0.

        On a move back (a bag looping, a simulator restarted) the filter
        restarts on the new clock at once, and start-up is ``now``.
        """
        back = self._clock.moved_back(now)
        if back > 0.0:
            self.restart(new_clock=True)
            self.restarts += 1
            self.started_at = now
        return back

    @property
    def estimate(self):
        """``(stamp, (x, y, yaw), cov3)`` or None before the filter starts."""
        if self.ekf is None:
            return None
        return self.stamp, self.ekf.pose, self.ekf.cov.copy()

    # -- the filter step ------------------------------------------------------
    def _driver(self, active):
        """The sensor whose messages step the filter, or None."""
        for name in MOTION_SOURCES + ('imu',):
            if name in active:
                return name
        return None

    def step(self, now):
        """Run the filter up to time ``now``; return log events.

        With odometry active the filter steps on each new odometry message
        (the other sensors' news is fused with it); without odometry on
        each new visual odometry message, and without either on each new
        IMU message. With ``gps_used``, see :meth:`_step_gps_mode`.
        Afterwards :attr:`new_estimates` lists the estimates made, oldest
        first (``(stamp, pose, cov3)``; GPS mode can make several a call).
        """
        self.new_estimates = []
        events = self._step(now)
        if self.updated and not self.new_estimates:
            self.new_estimates.append(self.estimate)
        return events

    def _step(self, now):
        if self.started_at is None:
            self.started_at = now
        events, self._notes = self._notes + self._check_sensors(now), []
        self.updated = False
        active = [n for n in self.used_sensors() if self.watches[n].active]
        if self.gps_used:
            return events + self._step_gps_mode(now, active)
        if self.ekf is None:
            self._last_predict = now
            return events + self._try_start(active)
        driver = self._driver(active)
        if driver is None or not self._fresh(driver):
            return events
        fresh = [n for n in active if self._fresh(n)]
        try:
            with np.errstate(over='ignore', invalid='ignore'):
                events += self._fuse(now, driver, active, fresh)
        except (ValueError, np.linalg.LinAlgError) as err:
            return events + self._restarted(err)
        self._advance_stamp(active)
        return events

    def _restarted(self, err):
        """Restart after ``err``; the warning event to log."""
        self.restart()
        self.restarts += 1
        return [('warn', 'filter restarted: %s; it starts again from the '
                 'next %s message' % (err, self._start_sensor_text()))]

    # -- robot_pose_ekf's GPS mode (gps_used) ----------------------------------
    def _step_gps_mode(self, now, active):
        """One step with ``gps_used``, as robot_pose_ekf does.

        The filter starts when both the IMU and GPS are active, at the fix
        and the IMU's heading: its output frame is the GPS frame, with the
        IMU's yaw taken as heading in it (with ``gps_frame_rotation``, as
        the prior of the heading). Then it steps at the oldest of the
        active sensors' newest stamps, at every such time since its last
        step (:meth:`_step_times`), where every sensor is read by
        interpolation: odometry (and visual odometry) increments since the
        last step, the IMU's yaw as absolute while GPS is active (relative
        otherwise), and each new fix on x, y (the first after GPS starts or
        returns is skipped).
        """
        if self.ekf is None:
            return self._start_gps_mode(active)
        if not active:
            return []
        t = min([now] + [self._latest[n].stamp for n in active])
        times = self._step_times(t, active)
        if not times:
            return []
        # With gps_kalman, step at each new fix's own stamp on the way
        # (not past the last filter time: later ones are never older).
        if self.gps_kalman and 'gps' in active:
            times = sorted(set(times + [r.stamp for r in self._history['gps']
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
            return self._restarted(err)
        if self.stamp is None or times[-1] > self.stamp:
            self.stamp, self.updated = times[-1], True
        return events

    def _step_times(self, t, active):
        """robot_pose_ekf's filter times after the last step, up to ``t``.

        robot_pose_ekf steps, ``freq`` times a second, at the oldest of its
        sensors' newest stamps. Here that is read off the stamps, not off
        when the node's timer fires or messages arrive: at each multiple
        of ``1/freq`` s up to ``t``, the oldest of the sensors' newest
        stamps not after it (the newest :data:`MAX_CATCH_UP` s of them).
        """
        stamps = {n: [r.stamp for r in self._history[n]] for n in active}
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

    def _start_gps_mode(self, active):
        if 'imu' not in active or 'gps' not in active:
            return []
        fix, imu = self._latest['gps'], self._latest['imu']
        if len(fix.measured) < 2 or not imu.measured:
            return []  # noted once when it came in
        t = fix.stamp
        yaw = self._value_at('imu', t)
        cov = np.zeros((3, 3))
        cov[0:2, 0:2], cov[2, 2] = fix.cov, imu.cov
        self.ekf = PlanarEkf(fix.value + (yaw,), cov, anchors=())
        if self.gps_frame_rotation is not None:
            self.ekf.add_rotation(self.gps_frame_rotation ** 2)
        self._time, self._gps_fused = t, t  # this fix is used up
        self._was_active = set(active)
        for name in active:
            self._ref[name] = self._value_at(name, t)
        if self.stamp is None or t > self.stamp:
            self.stamp, self.updated = t, True
        heading = 'the IMU heading'
        if self.gps_frame_rotation is not None:
            heading += ' give or take %.0f deg (gps_frame_rotation)' % (
                math.degrees(self.gps_frame_rotation))
        return [('info', 'filter started at the GPS fix and %s (gps_used: '
                 'the output frame is the GPS frame): x=%.3f y=%.3f yaw=%.3f'
                 % ((heading,) + self.ekf.pose))]

    def _fuse_at(self, t, active):
        """Predict to filter time ``t`` and fuse every active sensor there."""
        dt = t - self._time
        events = []
        now = {n: self._value_at(n, t) for n in active}
        ref = {n: self._ref[n] if n in self._was_active else None
               for n in SENSORS}
        if 'odom' in active and ref['odom'] is not None:
            increment = odom_increment(ref['odom'], now['odom'])
            self.ekf.predict(increment, increment_cov(
                increment, self._reading_at('odom', t), dt,
                scale=dt / self._period('odom', dt, t)))
        else:
            self.ekf.predict((0.0, 0.0, 0.0), no_motion_cov(dt))
        self._check_finite()
        imu, vo = self._reading_at('imu', t), self._reading_at('vo', t)
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
                vo.cov * (dt / self._period('vo', dt, t)), 'vo', vo.measured)
        for name in ('imu', 'vo'):
            (self.ekf.set_anchor if name in active
             else self.ekf.drop_anchor)(name)
        self._check_finite()
        if 'gps' in active:
            events += self._fuse_fix(t, ref['gps'] is None)
        else:
            self._gps_fused = None
        self._ref.update(now)
        return events

    def _fuse_fix(self, t, first):
        """Fuse the GPS position at ``t``; the first step after GPS starts
        or returns only reads it.

        As robot_pose_ekf: at every step, the fix (read at ``t``) pulls the
        position by the weight its covariance has against odometry's. With
        ``gps_kalman``: each fix once, with the Kalman gain.
        """
        if first:
            self._gps_fused = self._reading_at('gps', t).stamp
            return []
        if self.gps_kalman:
            fix = next(r for r in reversed(self._history['gps'])
                       if r.stamp <= t)
            if fix.stamp <= self._gps_fused:
                return []
            self._gps_fused, position = fix.stamp, fix.value
        else:
            fix, position = self._reading_at('gps', t), self._value_at('gps', t)
        if not fix.measured:
            return []
        distance = self.ekf.position_distance(position, fix.cov,
                                              fix.measured)
        if distance > GPS_GATE_SIGMAS:
            x, y, _ = self.ekf.pose
            text = self.inputs.warning(self.inputs.reject(
                'gps', GPS_JUMP, 'fix (%.2f, %.2f) is %.1f m (%.0f sd) from '
                'the estimate (%.2f, %.2f): not fused' % (
                    position + (math.hypot(position[0] - x, position[1] - y),
                                distance, x, y))), t,
                'gps on %s' % self.topics.get('gps', 'gps'))
            return [('warn', text)] if text else []
        if self.gps_kalman:
            self.ekf.update_position(position, fix.cov, fix.measured)
        else:
            odom = self._reading_at('odom', t)
            motion = (np.diag(odom.cov)[0:2] if 'odom' in self._was_active
                      else NO_ODOM_VARIANCE_RATE[0:2])
            self.ekf.blend_position(position, fix.cov,
                                    motion / (motion + np.diag(fix.cov)),
                                    fix.measured)
        self._check_finite()
        return []

    def _fresh(self, name):
        ref = self._ref[name]
        return ref is None or self._latest[name].seq != ref.seq

    def _start_sensor_text(self):
        if self.gps_used:
            return 'IMU and GPS'
        if self.odom_used:
            return 'odometry'
        return 'visual odometry' if self.vo_used else 'IMU'

    def _fuse(self, now, driver, active, fresh):
        """Predict to ``now`` with the driver; fuse the others' news."""
        events = []
        self._predict(driver, max(now - self._last_predict, 0.0))
        self._last_predict = now
        self._check_finite()
        for name in ('imu', 'vo'):
            relative = name in active and (name == 'imu' or name != driver)
            if not relative:
                self.ekf.drop_anchor(name)
                continue
            reading = self._latest[name]
            if not self.ekf.has_anchor(name) or self._ref[name] is None:
                # A new anchor: measure from here on (e.g. visual odometry
                # after odometry came back and took over the prediction).
                self._ref[name] = reading
                self.ekf.set_anchor(name)
                continue
            if name not in fresh:
                continue
            if not reading.measured:
                self.ekf.set_anchor(name)  # nothing measured: re-anchor
            elif name == 'imu':
                self.ekf.update_yaw_increment(
                    normalize_angle(reading.value - self._ref[name].value),
                    reading.cov, name)
            else:
                self.ekf.update_pose_increment(
                    odom_increment(self._ref[name].value, reading.value),
                    reading.cov, name, reading.measured)
            self._ref[name] = reading
            self._check_finite()
        return events

    def _check_finite(self):
        """ValueError unless the filter's mean and covariance are finite."""
        if not (np.all(np.isfinite(self.ekf.state))
                and np.all(np.isfinite(self.ekf.state_cov))):
            raise ValueError('the estimate is no longer finite')

    def _watch_time(self, now):
        """The time the sensor timeouts are judged at: while any used
        sensor still talks, when the last message came (a node starved of
        the CPU steps before it reads the messages queued meanwhile: that
        is no sensor's fault); ``now`` once all have been silent for
        :data:`ALL_SILENT_TIMEOUTS` sensor timeouts (a driver that died)."""
        seen = [self.watches[n].last_seen for n in self.used_sensors()
                if self.watches[n].last_seen is not None]
        if seen and now - max(seen) <= ALL_SILENT_TIMEOUTS * self.sensor_timeout:
            return max(seen)
        return now

    def _check_sensors(self, now):
        """Apply timeouts: a lost sensor is left out, a returning one re-based."""
        events = []
        at = self._watch_time(now)
        for name in self.used_sensors():
            change = self.watches[name].check(at)
            if change == 'lost':
                self._ref[name] = None
                if self.ekf is not None:
                    self.ekf.drop_anchor(name)
                events.append(('warn', '%s timed out: no message for %.2f s; '
                               'fusing without it' % (
                                   name, self.watches[name].timeout)))
            elif change in ('started', 'back'):
                # A returning sensor starts a new reference: its jump while
                # away (e.g. a restarted driver) is never fused. GPS is
                # absolute: its frame origin stays valid. In GPS mode the
                # references are values at filter times: the next step
                # takes a new one.
                self._ref[name] = (None if name == 'gps' or self.gps_used
                                   else self._latest[name])
                if name in ('imu', 'vo') and self.ekf is not None:
                    self.ekf.set_anchor(name)
                if change == 'back':
                    events.append(('info', '%s is back; fusing it again'
                                   % name))
        return events

    def _try_start(self, active):
        """Start at the first odometry (else visual odometry, else IMU)."""
        source = next((n for n in MOTION_SOURCES if self.used(n)), None)
        if source is not None:
            if source not in active:
                return []
            # The output frame starts at this pose: known exactly, whatever
            # the sensor's own uncertainty of it.
            first = self._latest[source]
            self.ekf = PlanarEkf(first.value, np.zeros((3, 3)), anchors=())
            where = 'the first %s pose' % (
                'odometry' if source == 'odom' else 'visual odometry')
        else:
            if 'imu' not in active:
                return []
            self.ekf = PlanarEkf((0.0, 0.0, 0.0), np.zeros((3, 3)), anchors=())
            where = 'the origin (no odometry used)'
        for name in active:
            self._ref[name] = self._latest[name]
            if name == 'imu' or (name == 'vo' and source != 'vo'):
                self.ekf.set_anchor(name)
        self._advance_stamp(active)
        x, y, yaw = self.ekf.pose
        return [('info', 'filter started at %s: x=%.3f y=%.3f yaw=%.3f'
                 % (where, x, y, yaw))]

    def _predict(self, driver, dt):
        """Predict with the driver's increment, or 'no motion' without one."""
        if driver in MOTION_SOURCES:
            reading, ref = self._latest[driver], self._ref[driver]
            increment = odom_increment(ref.value, reading.value)
            # An unmeasured component grows over the time the increment
            # spans (its two stamps), not over the filter's step: when
            # the step falls between two messages must not matter.
            self.ekf.predict(increment, increment_cov(
                increment, reading, reading.stamp - ref.stamp))
            self._ref[driver] = reading
        else:
            self.ekf.predict((0.0, 0.0, 0.0), no_motion_cov(dt))

    def _advance_stamp(self, active):
        """Stamp the estimate with the newest fused message; note progress.

        The stamp never goes back, not even across a :meth:`restart` (only
        on a new clock): an estimate no newer than the last is not news.
        """
        stamp = max(self._latest[n].stamp for n in active)
        if self.stamp is None or stamp > self.stamp:
            self.stamp = stamp
            self.updated = True

    # -- status ---------------------------------------------------------------
    def state(self):
        """'waiting for odom, imu', 'running' or 'running; dropped: imu'."""
        return state_text(self)

    def status_text(self, now, topics=None):
        """A human-readable status (:func:`rbx1_nav.estimation.status.status_text`)."""
        return status_text(self, now, topics)
