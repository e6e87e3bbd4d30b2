"""The fusion of pose_ekf, the one object its node feeds: when the filter
starts and restarts, and the sensor timeouts.

:class:`GyroOdomFusion` takes the sensors' readings through
:class:`rbx1_nav.estimation.sensors.SensorInputs` and runs the filter of
:mod:`rbx1_nav.estimation.ekf` on them, one run from each start to the
next restart: without GPS a
:class:`rbx1_nav.estimation.relative_run.RelativeRun` (it steps on each
new odometry message; without odometry, visual odometry; without either,
the IMU), with ``gps_used`` a :class:`rbx1_nav.estimation.gps_run.GpsRun`
(robot_pose_ekf's GPS mode). It applies the sensor timeouts, restarts the
filter should its estimate stop being finite or ROS time move backwards,
and gives its state as text through :mod:`rbx1_nav.estimation.status`.
No rospy.
"""
from rbx1_nav.common.ros_time import ClockWatch
from rbx1_nav.estimation.filter_run import StepFailed
from rbx1_nav.estimation.gps_run import GpsRun
from rbx1_nav.estimation.relative_run import RelativeRun
from rbx1_nav.estimation.sensors import SensorInputs
from rbx1_nav.estimation.status import state_text, status_text

__all__ = ['GyroOdomFusion']

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
    (:class:`rbx1_nav.estimation.gps_run.GpsRun`): it starts at a fix with
    the IMU's heading, takes the IMU's yaw as absolute while GPS is active
    and the fixes on x, y only (z is ignored). With ``gps_frame_rotation``
    (a prior standard deviation in rad) the IMU's heading is not taken as
    true in the GPS frame: the rotation between the two is a state, with
    prior ``N(0, gps_frame_rotation**2)``, that the fixes refine as the
    robot moves (each fix fused once with the Kalman gain, as with
    ``gps_kalman``).

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
        self._run = None
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
        stamp = None if new_clock or self._run is None else self._run.stamp
        if self.gps_used:
            self._run = GpsRun(self, stamp, self.freq, self.gps_kalman,
                               self.gps_frame_rotation)
        else:
            self._run = RelativeRun(self, stamp)
        if new_clock:
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

    # -- the run's state, as the node, the status and the tests read it ------
    @property
    def estimate(self):
        """``(stamp, (x, y, yaw), cov3)`` or None before the filter starts."""
        return self._run.estimate

    @property
    def ekf(self):
        """The filter (rbx1_nav.estimation.ekf.PlanarEkf), None before it
        starts."""
        return self._run.ekf

    @property
    def stamp(self):
        """The estimate's stamp: never back, but on a new clock."""
        return self._run.stamp

    @property
    def updated(self):
        """Whether the last :meth:`step` fused new data."""
        return self._run.updated

    @property
    def new_estimates(self):
        """The estimates the last :meth:`step` made, oldest first."""
        return self._run.new_estimates

    # -- the filter step ------------------------------------------------------
    def step(self, now):
        """Run the filter up to time ``now``; return log events.

        With odometry active the filter steps on each new odometry message
        (the other sensors' news is fused with it); without odometry on
        each new visual odometry message, and without either on each new
        IMU message. With ``gps_used``, see
        :class:`rbx1_nav.estimation.gps_run.GpsRun`. Afterwards
        :attr:`new_estimates` lists the estimates made, oldest first
        (``(stamp, pose, cov3)``; GPS mode can make several a call).
        """
        if self.started_at is None:
            self.started_at = now
        events, self._notes = self._notes + self._check_sensors(now), []
        active = [n for n in self.used_sensors() if self.watches[n].active]
        try:
            return events + self._run.step(now, active)
        except StepFailed as failed:
            return events + self._restarted(failed.cause)

    def _restarted(self, err):
        """Restart after ``err``; the warning event to log."""
        self.restart()
        self.restarts += 1
        return [('warn', 'filter restarted: %s; it starts again from the '
                 'next %s message' % (err, self._start_sensor_text()))]

    def _start_sensor_text(self):
        if self.gps_used:
            return 'IMU and GPS'
        if self.odom_used:
            return 'odometry'
        return 'visual odometry' if self.vo_used else 'IMU'

    # -- sensor timeouts -------------------------------------------------------
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
                self._run.lost(name)
                events.append(('warn', '%s timed out: no message for %.2f s; '
                               'fusing without it' % (
                                   name, self.watches[name].timeout)))
            elif change in ('started', 'back'):
                self._run.back(name)
                if change == 'back':
                    events.append(('info', '%s is back; fusing it again'
                                   % name))
        return events

    # -- status ---------------------------------------------------------------
    def state(self):
        """'waiting for odom, imu', 'running' or 'running; dropped: imu'."""
        return state_text(self)

    def status_text(self, now, topics=None):
        """A human-readable status (:func:`rbx1_nav.estimation.status.status_text`)."""
        return status_text(self, now, topics)
