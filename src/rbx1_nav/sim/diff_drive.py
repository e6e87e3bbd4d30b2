"""Kinematic differential-drive robot: the model behind nodes/fake_turtlebot.py.

A stand-in for the ArbotiX fake robot of *ROS By Example*, with what that one
lacks: a command watchdog, speed and acceleration limits, exact arc
integration, non-zero covariances and an optional "realistic" mode in which
odometry drifts from the truth the way an uncalibrated robot's does.

Three views of the same motion are kept apart:

* **truth** - where the robot really is (integrated from the velocity the
  base actually executes, after watchdog, clamping and acceleration limits);
* **wheels** - what the encoders read: the true wheel travel plus optional
  noise (``encoder_noise``);
* **odometry** - the pose the robot's driver computes from the encoder
  readings; scaled by ``*_scale_error`` (a miscalibrated robot) and then by
  ``odom_*_scale_correction`` (the driver's calibration parameters);
* a **gyro** measures the true yaw rate plus bias and noise, independent of
  the odometry errors.

The model steps a whole fleet at once: :class:`DiffDriveFleet` holds N
robots of one configuration in numpy arrays (one row per robot), so N robots
cost one array operation per step (nodes/fake_fleet.py); a
:class:`FleetRobot` reads one robot's row as scalars. :class:`DiffDriveSim`,
the single robot of nodes/fake_turtlebot.py, is the same model in plain floats
(numpy's cost per call would be most of a single robot's).

Time is plain float seconds supplied by the caller (the node passes ROS time),
so the model behaves identically at any simulation speed. No rospy here.
"""
import math
from collections import deque
from dataclasses import fields

import numpy as np

from rbx1_nav.common.params import bounds, number
from rbx1_nav.sim.params import DIFF_DRIVE_PARAMS, declared_fields, optional_integer
from rbx1_nav.transform_utils import Pose2D

__all__ = ['DiffDriveConfig', 'DiffDriveSim', 'DiffDriveFleet', 'FleetRobot',
           'arc_steps', 'columns', 'wrap_angles', 'covariance_from_diagonal']


def wrap_angles(angles):
    """``angles`` (rad, an array) wrapped to [-pi, pi], as math.remainder does."""
    angles = np.asarray(angles, dtype=float)
    return angles - 2.0 * math.pi * np.rint(angles / (2.0 * math.pi))


def columns(*arrays):
    """An (N, len(arrays)) array of the N-arrays ``arrays`` as its columns
    (what np.column_stack does, at a fraction of its cost for a few robots)."""
    out = np.empty((len(arrays[0]), len(arrays)))
    for i, column in enumerate(arrays):
        out[:, i] = column
    return out


def arc_steps(poses, ds, dtheta):
    """The poses (an (N, 3) array of x, y, yaw) after travelling ``ds``
    metres while turning ``dtheta`` rad (arrays of N): the array form of
    rbx1_nav.common.geometry.arc_step.

    The path is a circular arc (a straight line when ``dtheta`` is 0), which
    is what a differential drive traces at constant (v, w): exact, unlike
    forward Euler. The chord of the arc is ``ds * sin(dtheta/2)/(dtheta/2)``
    and points along the mean heading; numpy's sinc keeps that well defined
    at ``dtheta == 0``.
    """
    half = 0.5 * dtheta
    straight = half == 0.0
    half_or_one = np.where(straight, 1.0, half)
    chord = ds * np.where(straight, 1.0, np.sin(half_or_one) / half_or_one)
    heading = poses[:, 2] + half
    return columns(poses[:, 0] + chord * np.cos(heading),
                    poses[:, 1] + chord * np.sin(heading),
                    wrap_angles(poses[:, 2] + dtheta))


def covariance_from_diagonal(diagonal):
    """Row-major 6x6 covariance (a list of 36 floats) with ``diagonal``.

    Raises ValueError unless ``diagonal`` holds six finite positive numbers:
    a zero variance claims perfect knowledge, which makes filters such as
    robot_pose_ekf reject the message.
    """
    diag = np.asarray(diagonal, dtype=float)
    if diag.shape != (6,) or not np.all(np.isfinite(diag)) or np.any(diag <= 0):
        raise ValueError('a covariance diagonal needs six finite positive '
                         'variances, got %r' % (diagonal,))
    return np.diag(diag).ravel().tolist()


@declared_fields(DIFF_DRIVE_PARAMS)
class DiffDriveConfig:
    """Parameters of the simulated base; defaults are an ideal TurtleBot.

    Every field is a private parameter of the node with the same name,
    declared (default, check, bounds) in rbx1_nav.sim.params.DIFF_DRIVE_PARAMS;
    ``PARAMS`` holds the declarations of all the fields.
    """

    def problems(self):
        """Human-readable list of invalid values; empty when all are usable.

        Every number must be an int or float within its declared bounds
        (they keep the model's arithmetic finite); ``seed`` must be None or
        an int >= 0. The numbers come first, then the other fields.
        """
        found = []
        for spec in sorted(self.PARAMS, key=lambda spec: spec.check is not number):
            value = getattr(self, spec.name)
            try:
                if spec.check is number and (isinstance(value, bool) or
                                             not isinstance(value, (int, float))):
                    raise ValueError('%s must be a number, got %r' % (spec.name, value))
                if spec.check is optional_integer and value is not None and (
                        isinstance(value, bool) or not isinstance(value, int)):
                    raise ValueError('%s must be an integer %s, got %r'
                                     % (spec.name, bounds(spec), value))
                spec.check(spec.name, value, **spec.options)
            except ValueError as err:
                found.append(str(err))
        return found

    @classmethod
    def from_params(cls, raw, prefix=''):
        """A config from raw parameter values, e.g. as rospy.get_param returns.

        ``raw`` maps field names to values; missing fields keep their
        defaults. Numbers may be numeric strings (YAML reads 1e6 as one).
        Raises ValueError naming every bad value as ``prefix + name``.
        """
        specs = {spec.name: spec for spec in cls.PARAMS}
        values, found = {}, []
        for name, value in raw.items():
            if name not in specs:
                raise ValueError('%s%s is not a fake robot parameter' % (prefix, name))
            try:
                values[name] = specs[name].check(prefix + name, value,
                                                 **specs[name].options)
            except ValueError as err:
                found.append(str(err))
        if found:
            raise ValueError('; '.join(found))
        return cls(**values)

    @classmethod
    def names(cls):
        """Names of all parameters, in declaration order."""
        return [f.name for f in fields(cls)]


def _max_change(accel_limit, dt):
    """Largest speed change allowed in ``dt`` s; unbounded for a 0 limit."""
    return accel_limit * dt if accel_limit > 0 else float('inf')


def _approach(current, target, max_change):
    """``target``, or ``current`` moved toward it by at most ``max_change``
    (arrays of N speeds).

    The result never passes ``target``, not even by a rounding error, so a
    speed at its limit stays within it.
    """
    if max_change == float('inf'):
        return target
    moved = current + np.copysign(max_change, target - current)
    moved = np.minimum(np.maximum(moved, np.minimum(current, target)),
                       np.maximum(current, target))
    return np.where(np.abs(target - current) <= max_change, target, moved)


def _ns(seconds):
    """``seconds`` as integer nanoseconds."""
    return int(round(seconds * 1e9))


def _checked(config, size=1):
    """``config`` (default: the ideal robot) once its values and ``size`` hold;
    else ValueError."""
    config = config or DiffDriveConfig()
    problems = config.problems()
    if problems:
        raise ValueError('invalid fake robot parameters: ' + '; '.join(problems))
    if isinstance(size, bool) or not isinstance(size, int) or size < 1:
        raise ValueError('a fleet needs at least one robot, got %r' % (size,))
    return config


def _generators(seed):
    """(encoder noise, gyro noise) generators from ``seed``: separate streams,
    so turning one noise on leaves the other's draws as they were."""
    return tuple(np.random.default_rng(s) for s in np.random.SeedSequence(seed).spawn(2))


def _queued(cfg, v, w, stamp):
    """((due ns, v, w) to queue, problem) for a command received at ``stamp``
    s: see :meth:`DiffDriveFleet.command`."""
    v, w = float(v), float(w)
    due = _ns(stamp) + _ns(cfg.command_latency)
    if not (math.isfinite(v) and math.isfinite(w)):
        return (due, 0.0, 0.0), 'non-finite'
    cv = max(-cfg.max_linear_speed, min(cfg.max_linear_speed, v))
    cw = max(-cfg.max_angular_speed, min(cfg.max_angular_speed, w))
    return (due, cv, cw), ('clamped' if (cv, cw) != (v, w) else None)


def _clock(last, now):
    """(time of this step ns, seconds since ``last`` or None, restarted) for
    a step to ``now`` ns: the first only sets the clock, one at ``last``
    integrates nothing, one before it restarts the clock there."""
    if last is None or now < last:
        return now, None, last is not None
    dt = (now - last) * 1e-9
    return now, (dt if dt != 0.0 else None), False


def gyro_variances(cfg, period):
    """(yaw, yaw rate) variances to report for the gyro of ``cfg`` at ``period`` s.

    The rate variance is that of one reading plus the bias squared; the
    yaw variance is the error the integrated yaw gathers in one second.
    Both have a small floor so they are never zero.
    """
    rate_var = cfg.gyro_noise_density ** 2 / period + cfg.gyro_bias ** 2
    yaw_var = cfg.gyro_noise_density ** 2 * 1.0 + cfg.gyro_bias ** 2
    return max(yaw_var, 1e-6), max(rate_var, 1e-6)


class DiffDriveFleet:
    """N simulated bases of one configuration: feed them commands and
    times, read their state (row i is robot i).

    Call :meth:`command` for every cmd_vel of robot i and :meth:`step` at the
    control rate: every robot steps at the same times. Each step holds one
    velocity per robot over the interval since the previous step
    (zero-order hold), chosen from the robot's newest command executable by
    the step's time, so a command takes effect within one step of arriving
    and the watchdog stops a robot within ``cmd_timeout`` plus one step of
    its last command.

    State, arrays with one row per robot: ``truth`` and ``odom`` (N, 3: x,
    y, yaw), ``velocity`` and ``odom_velocity`` (N, 2: v, w),
    ``wheel_angles`` and ``wheel_velocities`` (N, 2: left, right),
    ``gyro_rate`` and ``gyro_yaw`` (N), ``timed_out`` (N, bool). The noise
    of all robots comes from two generators seeded by ``config.seed``, drawn
    for the whole fleet each step: the gyros' every step, the encoders'
    on the steps where a base moves.
    """

    def __init__(self, size, config=None):
        self.config = _checked(config, size)
        self.size = size
        # Encoder and gyro noise from separate streams, and encoder noise
        # drawn only while a base moves (at rest it is zero): a course
        # meets the same noise whenever it starts.
        self._rng, self._gyro_rng = _generators(self.config.seed)
        # Per robot: (executable at, v, w) in arrival order.
        self._pending = [deque() for _ in range(size)]
        self._cmd = np.zeros((size, 2))
        # Times in integer ns (as ROS stamps are): a course's steps and
        # commands then fall alike whatever the clock read when it began.
        self._cmd_time = np.full(size, -np.inf)  # ns: when the executing command became due
        self._time = None  # ns of the last step
        self.timed_out = np.zeros(size, dtype=bool)  # True while the watchdog holds a base
        self._truth = np.zeros((size, 3))
        self.odom = np.zeros((size, 3))
        self._commanded = np.zeros((size, 2))  # (v, w) executed over the last step
        self._velocity = np.zeros((size, 2))       # true (v, w) over the last step
        self.odom_velocity = np.zeros((size, 2))
        self.wheel_angles = np.zeros((size, 2))      # encoder readings, rad
        self.wheel_velocities = np.zeros((size, 2))  # rad/s over the last step
        self.gyro_rate = np.zeros(size)            # rad/s, measured
        self.gyro_yaw = np.zeros(size)             # rad, integral of the measured rate

    @property
    def truth(self):
        """(N, 3): where the bases really are (x, y, yaw)."""
        return self._truth

    @property
    def velocity(self):
        """(N, 2): the (v, w) the bases really moved at over the last step."""
        return self._velocity

    @property
    def command_times(self):
        """(N,): ns when each base's newest executed command became due
        (-inf: none yet); the watchdog counts ``cmd_timeout`` from it."""
        return self._cmd_time

    def robot(self, index):
        """Robot ``index`` read as scalars: a :class:`FleetRobot`."""
        return FleetRobot(self, index)

    def command(self, robot, v, w, stamp):
        """Queue a velocity command for robot ``robot`` received at ``stamp`` s.

        Returns None for a usable command, ``'non-finite'`` when v or w is NaN
        or infinite (the command is replaced by a stop) or ``'clamped'`` when
        a speed exceeded its limit (it is executed at the limit).
        """
        queued, problem = _queued(self.config, v, w, stamp)
        self._pending[robot].append(queued)
        return problem

    def step(self, now):
        """Advance every robot to ``now`` seconds; True if time advanced.

        The first call only sets the clock. A call with a time at or before
        the previous one integrates nothing; time moving backwards (a
        restarted simulation clock) re-bases the clock there and drops the
        commands received so far, which stops the bases until their next one.
        """
        now = _ns(now)
        dt = self._advance_clock(now)
        if dt is None:
            return False
        v, w = self._execute(now, dt)
        self._commanded = columns(v, w)
        self._move(v, w, dt)
        return True

    def _advance_clock(self, now):
        """The seconds from the previous step to ``now`` (ns); None when
        time did not advance (see :meth:`step`)."""
        self._time, dt, restarted = _clock(self._time, now)
        if restarted:  # forget old commands
            for queue in self._pending:
                queue.clear()
            self._cmd_time[:] = -np.inf
        return dt

    def _move(self, v, w, dt):
        """The bases execute (v, w) exactly for ``dt`` s: truth, wheels,
        odometry and gyro follow."""
        self._velocity = columns(v, w)
        self._truth = arc_steps(self._truth, v * dt, w * dt)
        self._update_wheels_and_odometry(v, w, dt)
        self._update_gyro(w, dt)

    def _execute(self, now, dt):
        """The (v, w) arrays the bases execute over the step ending at
        ``now`` (ns)."""
        cfg = self.config
        for robot, queue in enumerate(self._pending):
            while queue and queue[0][0] <= now:
                self._cmd_time[robot], v, w = queue.popleft()
                self._cmd[robot] = (v, w)
        # A robot that never had a command (time -inf) is timed out too.
        self.timed_out = now - self._cmd_time > _ns(cfg.cmd_timeout)
        target = np.where(self.timed_out[:, None], 0.0, self._cmd)
        return (_approach(self._commanded[:, 0], target[:, 0],
                          _max_change(cfg.accel_limit_linear, dt)),
                _approach(self._commanded[:, 1], target[:, 1],
                          _max_change(cfg.accel_limit_angular, dt)))

    def _update_wheels_and_odometry(self, v, w, dt):
        """Encoder readings from the true motion, then odometry from them.

        A wheel whose true radius is ``*_wheel_radius_error`` times the
        nominal one turns that much less for the same ground travel; the
        driver turns each wheel's angle back into travel with the nominal
        radius times its ``*_wheel_radius_multiplier``, and the turn with
        the wheel separation times ``wheel_separation_multiplier``.
        """
        cfg = self.config
        half_track = 0.5 * cfg.wheel_separation
        travel = columns(v - w * half_track, v + w * half_track) * dt
        if cfg.encoder_noise > 0 and travel.any():
            # Variance grows with distance travelled, not with the step count.
            travel += (cfg.encoder_noise * np.sqrt(np.abs(travel))
                       * self._rng.standard_normal(travel.shape))
        turned = travel / np.array([cfg.left_wheel_radius_error,
                                    cfg.right_wheel_radius_error])
        self._update_odometry(turned / cfg.wheel_radius, dt)

    def _update_odometry(self, angles, dt):
        """The driver's odometry from the encoders' wheel ``angles`` (rad,
        (N, 2): left, right) turned over the last ``dt`` s."""
        cfg = self.config
        self.wheel_angles += angles
        self.wheel_velocities = angles / dt
        wheels = angles * cfg.wheel_radius * np.array(
            [cfg.left_wheel_radius_multiplier, cfg.right_wheel_radius_multiplier])
        left, right = wheels[:, 0], wheels[:, 1]
        ds = (0.5 * (left + right) * cfg.linear_scale_error
              * cfg.odom_linear_scale_correction)
        dtheta = ((right - left)
                  / (cfg.wheel_separation * cfg.wheel_separation_multiplier)
                  * cfg.angular_scale_error * cfg.odom_angular_scale_correction)
        self.odom = arc_steps(self.odom, ds, dtheta)
        self.odom_velocity = columns(ds / dt, dtheta / dt)

    def _update_gyro(self, w, dt):
        """A z-axis gyro per robot: true yaw rate + bias + white noise, integrated."""
        cfg = self.config
        rate = w + cfg.gyro_bias
        if cfg.gyro_noise_density > 0:
            rate = rate + (cfg.gyro_noise_density / math.sqrt(dt)
                           * self._gyro_rng.standard_normal(self.size))
        self.gyro_rate = rate
        self.gyro_yaw = wrap_angles(self.gyro_yaw + rate * dt)

    def gyro_variances(self, period):
        """(yaw, yaw rate) variances to report for the gyro at ``period`` s
        (:func:`gyro_variances`)."""
        return gyro_variances(self.config, period)


class FleetRobot:
    """Robot ``index`` of a :class:`DiffDriveFleet`, read as scalars.

    ``truth`` and ``odom`` are Pose2D, ``velocity`` and ``odom_velocity``
    (v, w) tuples, ``wheel_angles`` and ``wheel_velocities`` [left, right]
    lists, ``gyro_rate``, ``gyro_yaw`` and ``command_time`` floats,
    ``timed_out`` a bool;
    :meth:`command` queues a command for this robot.
    """

    def __init__(self, fleet, index):
        self.fleet = fleet
        self.index = index
        self.config = fleet.config

    def command(self, v, w, stamp):
        """Queue a velocity command received at ``stamp`` seconds; see
        :meth:`DiffDriveFleet.command`."""
        return self.fleet.command(self.index, v, w, stamp)

    def gyro_variances(self, period):
        """(yaw, yaw rate) variances to report for the gyro at ``period`` s."""
        return self.fleet.gyro_variances(period)

    @property
    def truth(self):
        return Pose2D(*(float(c) for c in self.fleet.truth[self.index]))

    @property
    def odom(self):
        return Pose2D(*(float(c) for c in self.fleet.odom[self.index]))

    @property
    def velocity(self):
        return tuple(float(c) for c in self.fleet.velocity[self.index])

    @property
    def odom_velocity(self):
        return tuple(float(c) for c in self.fleet.odom_velocity[self.index])

    @property
    def command_time(self):
        """Seconds when the newest command it ran became due; None before any."""
        due = float(self.fleet.command_times[self.index])
        return None if math.isinf(due) else due * 1e-9

    @property
    def wheel_angles(self):
        return [float(c) for c in self.fleet.wheel_angles[self.index]]

    @property
    def wheel_velocities(self):
        return [float(c) for c in self.fleet.wheel_velocities[self.index]]

    @property
    def gyro_rate(self):
        return float(self.fleet.gyro_rate[self.index])

    @property
    def gyro_yaw(self):
        return float(self.fleet.gyro_yaw[self.index])

    @property
    def timed_out(self):
        return bool(self.fleet.timed_out[self.index])


class DiffDriveSim:
    """One simulated base (nodes/fake_turtlebot.py): :class:`DiffDriveFleet`'s
    model for one robot in plain floats, read as :class:`FleetRobot` reads a
    row. At 50 Hz numpy's cost per call, not the arithmetic, is the step's
    cost: a one-row fleet took 70 % of an idle robot's CPU. The same
    operations in the same order, and the same noise drawn from the same
    generators, give the same floats as a fleet of one
    (test_diff_drive_fleet checks it, step by step).

    Call :meth:`command` for every cmd_vel and :meth:`step` at the control
    rate; :class:`DiffDriveFleet` says how a step treats the commands.
    """

    size = 1

    def __init__(self, config=None):
        self.config = _checked(config)
        self._rng, self._gyro_rng = _generators(self.config.seed)
        self._pending = deque()  # (executable at ns, v, w) in arrival order
        self._cmd = (0.0, 0.0)
        self._cmd_time = -math.inf  # ns (a float, as a fleet's array holds it)
        self._time = None
        self.timed_out = False  # as a fleet before its first step
        self.truth = Pose2D(0.0, 0.0, 0.0)
        self.odom = Pose2D(0.0, 0.0, 0.0)
        self.velocity = (0.0, 0.0)
        self.odom_velocity = (0.0, 0.0)
        self.wheel_angles = [0.0, 0.0]
        self.wheel_velocities = [0.0, 0.0]
        self.gyro_rate = 0.0
        self.gyro_yaw = 0.0

    def robot(self, index):
        """Itself (a fleet's interface, for a fleet of one)."""
        if index != 0:
            raise IndexError('a single robot has only robot 0, not %r' % (index,))
        return self

    @property
    def command_time(self):
        """Seconds when the newest command it ran became due; None before any."""
        return None if math.isinf(self._cmd_time) else self._cmd_time * 1e-9

    def command(self, v, w, stamp):
        """Queue a velocity command received at ``stamp`` seconds; see
        :meth:`DiffDriveFleet.command`."""
        queued, problem = _queued(self.config, v, w, stamp)
        self._pending.append(queued)
        return problem

    def step(self, now):
        """Advance the simulation to ``now`` seconds; True if time advanced
        (see :meth:`DiffDriveFleet.step`)."""
        now = _ns(now)
        self._time, dt, restarted = _clock(self._time, now)
        if restarted:  # forget old commands
            self._pending.clear()
            self._cmd_time = -math.inf
        if dt is None:
            return False
        cfg = self.config
        queue = self._pending
        while queue and queue[0][0] <= now:
            cmd_time, v, w = queue.popleft()
            self._cmd_time, self._cmd = float(cmd_time), (v, w)
        self.timed_out = now - self._cmd_time > _ns(cfg.cmd_timeout)
        target_v, target_w = (0.0, 0.0) if self.timed_out else self._cmd
        v = _approach_one(self.velocity[0], target_v, _max_change(cfg.accel_limit_linear, dt))
        w = _approach_one(self.velocity[1], target_w, _max_change(cfg.accel_limit_angular, dt))
        self.velocity = (v, w)
        self.truth = _arc_step_one(self.truth, v * dt, w * dt)
        self._wheels_and_odometry(v, w, dt)
        rate = w + cfg.gyro_bias
        if cfg.gyro_noise_density > 0:
            rate = rate + (cfg.gyro_noise_density / math.sqrt(dt)
                           * float(self._gyro_rng.standard_normal(1)[0]))
        self.gyro_rate = rate
        self.gyro_yaw = _wrap_one(self.gyro_yaw + rate * dt)
        return True

    def _wheels_and_odometry(self, v, w, dt):
        """DiffDriveFleet._update_wheels_and_odometry for one robot."""
        cfg = self.config
        half_track = 0.5 * cfg.wheel_separation
        travel = [(v - w * half_track) * dt, (v + w * half_track) * dt]
        if cfg.encoder_noise > 0 and (travel[0] != 0.0 or travel[1] != 0.0):
            noise = self._rng.standard_normal((1, 2))[0]
            travel = [t + cfg.encoder_noise * math.sqrt(abs(t)) * float(z)
                      for t, z in zip(travel, noise)]
        angles = [travel[0] / cfg.left_wheel_radius_error / cfg.wheel_radius,
                  travel[1] / cfg.right_wheel_radius_error / cfg.wheel_radius]
        self.wheel_angles = [total + a for total, a in zip(self.wheel_angles, angles)]
        self.wheel_velocities = [a / dt for a in angles]
        left = angles[0] * cfg.wheel_radius * cfg.left_wheel_radius_multiplier
        right = angles[1] * cfg.wheel_radius * cfg.right_wheel_radius_multiplier
        ds = (0.5 * (left + right) * cfg.linear_scale_error
              * cfg.odom_linear_scale_correction)
        dtheta = ((right - left)
                  / (cfg.wheel_separation * cfg.wheel_separation_multiplier)
                  * cfg.angular_scale_error * cfg.odom_angular_scale_correction)
        self.odom = _arc_step_one(self.odom, ds, dtheta)
        self.odom_velocity = (ds / dt, dtheta / dt)

    def gyro_variances(self, period):
        """(yaw, yaw rate) variances to report for the gyro at ``period`` s
        (:func:`gyro_variances`)."""
        return gyro_variances(self.config, period)


def _wrap_one(angle):
    """wrap_angles for one angle."""
    return angle - 2.0 * math.pi * round(angle / (2.0 * math.pi))


def _approach_one(current, target, max_change):
    """_approach for one speed."""
    if max_change == float('inf'):
        return target
    moved = current + math.copysign(max_change, target - current)
    moved = min(max(moved, min(current, target)), max(current, target))
    return target if abs(target - current) <= max_change else moved


def _arc_step_one(pose, ds, dtheta):
    """arc_steps for one pose (a Pose2D). numpy's sin and cos, not math's:
    they differ in the last bit (numpy's are vectorised), and a course's
    figures are to be the same on either model."""
    half = 0.5 * dtheta
    chord = ds * (1.0 if half == 0.0 else float(np.sin(half)) / half)
    heading = pose.yaw + half
    return Pose2D(pose.x + chord * float(np.cos(heading)),
                  pose.y + chord * float(np.sin(heading)), _wrap_one(pose.yaw + dtheta))
