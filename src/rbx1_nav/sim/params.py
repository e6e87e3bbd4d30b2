"""The fake robot's parameters, every one declared here once with
rbx1_nav.common.params.param, for nodes/fake_turtlebot.py (one robot) and
nodes/fake_fleet.py (every robot of a fleet takes the same values).

TOPIC_PARAMS are read by the ROS side (rbx1_nav.sim.topics_ros and
loop_ros). DIFF_DRIVE_PARAMS are the settings of the kinematic model and
PHYSICS_PARAMS the physics robot's own: the fields of
rbx1_nav.sim.diff_drive.DiffDriveConfig and
rbx1_nav.sim.physics.PhysicsConfig are these declarations
(:func:`declared_fields`), with their defaults, checks and bounds. A node
reads the model's settings as given (PARAMS) and the model checks them when
it is made, so a physics setting counts only with ~physics. No rospy here.
"""
from dataclasses import dataclass
from typing import Any

from rbx1_nav.common.params import POSITIVE, flag, frame, integer, number, param, raw, text
from rbx1_nav.common.params_lists import names, number_list
from rbx1_nav.sim.floors import floor_name

__all__ = ['PARAMS', 'ROBOTS', 'TOPIC_PARAMS', 'DIFF_DRIVE_PARAMS', 'PHYSICS_PARAMS',
           'declared_fields', 'optional_integer', 'DEFAULT_COVARIANCE_DIAGONAL',
           'MAX_ROBOTS', 'WARN_PERIOD', 'MAX_CATCH_UP', 'MIN_RATE', 'MAX_RATE',
           'GPS_UNKNOWN_VARIANCE']

WARN_PERIOD = 5.0  # s between repeats of the same warning
MAX_CATCH_UP = 1.0  # s of ROS time the loop replays step by step when late
# Bounds of ~rate (Hz): the loop steps every 1/~rate s of ROS time, so a
# huge rate would be a zero period (an endless catch-up) and a tiny one a
# sleep too long for the OS.
MIN_RATE, MAX_RATE = 0.01, 1000.0
MAX_GPS_NOISE = 1000.0  # m, bound of ~gps_noise
GPS_UNKNOWN_VARIANCE = 1e6  # reported for z and the orientation (not measured)
MAX_ROBOTS = 1000  # bound of the length of fake_fleet's ~robots
# x, y, z, roll, pitch, yaw. A planar base observes only x, y and yaw; the
# large values for the rest follow the TurtleBot driver's convention.
DEFAULT_COVARIANCE_DIAGONAL = (1e-3, 1e-3, 1e6, 1e6, 1e6, 1e-3)


def optional_integer(name, value, **options):
    """None, or ``value`` as rbx1_nav.common.params.integer reads it."""
    return None if value is None else integer(name, value, **options)


COVARIANCE = dict(length=6, **POSITIVE)
#: The parameters of one robot's topics, frames and loop.
TOPIC_PARAMS = (
    param('rate', 50.0, number, 'Hz', 'simulation steps per second',
          minimum=MIN_RATE, maximum=MAX_RATE),
    param('physics', False, flag, '',
          'a robot with real dynamics on MuJoCo (rbx1_nav.sim.physics)'),
    param('odom_frame', 'odom', frame, '', 'odometry frame'),
    param('base_frame', 'base_footprint', frame, '', 'robot frame'),
    param('ground_truth_frame', 'world', frame, '',
          'frame of ground_truth and gps; tf to odom_frame is static'),
    param('imu_frame', '', frame, '', "frame of imu_data; '' = base_frame",
          allow_empty=True),
    param('publish_tf', True, flag, '', 'publish odom_frame -> base_frame'),
    param('publish_imu', False, flag, '', 'publish the gyro on imu_data'),
    param('publish_gps', False, flag, '', 'publish noisy true x, y on gps'),
    param('gps_noise', 0.3, number, 'm', 'GPS noise (1 sigma)',
          maximum=MAX_GPS_NOISE, **POSITIVE),
    param('gps_rate', 1.0, number, 'Hz', 'GPS fixes per second',
          minimum=MIN_RATE, maximum=MAX_RATE),
    param('left_wheel_joint', 'left_wheel_joint', text, '', 'joint name'),
    param('right_wheel_joint', 'right_wheel_joint', text, '', 'joint name'),
    param('pose_covariance_diagonal', list(DEFAULT_COVARIANCE_DIAGONAL),
          number_list, '', 'odom pose variances x y z roll pitch yaw',
          **COVARIANCE),
    param('twist_covariance_diagonal', list(DEFAULT_COVARIANCE_DIAGONAL),
          number_list, '', 'odom twist variances', **COVARIANCE),
)


def _model(name, default, minimum, maximum, unit, doc, allow_zero=False):
    """A numeric setting of the kinematic model. The maxima are far beyond
    any real base but keep the model's arithmetic finite (no inf pose, no
    endless loop)."""
    return param(name, default, number, unit, doc + ' (rbx1_nav.sim.diff_drive)',
                 minimum=minimum, maximum=maximum, allow_zero=allow_zero)


#: The kinematic model's settings (DiffDriveConfig's fields, in order);
#: the defaults are an ideal TurtleBot.
DIFF_DRIVE_PARAMS = (
    _model('wheel_separation', 0.26, 1e-3, 10.0, 'm',
           'between the wheel contact points'),
    _model('wheel_radius', 0.033, 1e-3, 10.0, 'm', 'of both wheels, nominal'),
    _model('max_linear_speed', 0.5, 0.0, 100.0, 'm/s',
           'larger commands are clamped'),
    _model('max_angular_speed', 3.0, 0.0, 100.0, 'rad/s',
           'larger commands are clamped'),
    _model('accel_limit_linear', 0.0, 0.0, 1e6, 'm/s^2', '0 = unlimited',
           allow_zero=True),
    _model('accel_limit_angular', 0.0, 0.0, 1e6, 'rad/s^2', '0 = unlimited',
           allow_zero=True),
    _model('cmd_timeout', 0.5, 0.0, 1e6, 's', 'without cmd_vel before stopping'),
    _model('command_latency', 0.0, 0.0, 60.0, 's',
           'between receipt and execution', allow_zero=True),
    _model('linear_scale_error', 1.0, 0.0, 100.0, '',
           'odometry distance / true distance'),
    _model('angular_scale_error', 1.0, 0.0, 100.0, '',
           'odometry rotation / true rotation: a wheel base that is off'),
    _model('odom_linear_scale_correction', 1.0, 0.0, 100.0, '',
           "the driver's linear calibration factor"),
    _model('odom_angular_scale_correction', 1.0, 0.0, 100.0, '',
           "the driver's angular calibration factor"),
    _model('left_wheel_radius_error', 1.0, 0.0, 100.0, '',
           'true radius / nominal radius'),
    _model('right_wheel_radius_error', 1.0, 0.0, 100.0, '',
           'true radius / nominal radius'),
    # The driver-side corrections under diff_drive_controller's names. Its
    # odometry uses them; the physics robot's driver also turns cmd_vel
    # into wheel speeds with them, as diff_drive_controller does (the
    # kinematic robot's base runs cmd_vel exactly, whatever its wheels):
    _model('left_wheel_radius_multiplier', 1.0, 0.0, 100.0, '',
           "diff_drive_controller's correction"),
    _model('right_wheel_radius_multiplier', 1.0, 0.0, 100.0, '',
           "diff_drive_controller's correction"),
    _model('wheel_separation_multiplier', 1.0, 0.0, 100.0, '',
           "diff_drive_controller's correction"),
    _model('encoder_noise', 0.0, 0.0, 1.0, 'm/sqrt(m)',
           'per sqrt(m) of wheel travel (1 sigma)', allow_zero=True),
    _model('gyro_noise_density', 0.0, 0.0, 10.0, 'rad/s/sqrt(Hz)',
           'white rate noise', allow_zero=True),
    _model('gyro_bias', 0.0, -10.0, 10.0, 'rad/s', 'constant rate offset',
           allow_zero=True),
    param('seed', None, optional_integer, '',
          'of the noise; none: fresh random noise each run '
          '(rbx1_nav.sim.diff_drive)', minimum=0),
)


def _physical(name, default, minimum, maximum, unit, doc, allow_zero=False):
    """A numeric physics robot setting."""
    return param(name, default, number, unit, doc + ' (rbx1_nav.sim.physics)',
                 minimum=minimum, maximum=maximum, allow_zero=allow_zero)


#: The physics robot's own settings (PhysicsConfig's fields beyond
#: DiffDriveConfig's, in order).
PHYSICS_PARAMS = (
    param('floor', 'carpet', floor_name, '',  # rbx1_nav.sim.floors.FLOORS
          'carpet or tile (rbx1_nav.sim.physics)'),
    _physical('mass', 6.0, 0.0, 1000.0, 'kg',
              "the whole robot (the URDF's: base 5.8, wheels 0.1 each); "
              'its inertias scale with it'),
    _physical('wheel_separation_error', 1.0, 0.0, 100.0, '',
              'true / nominal separation'),
    _physical('motor_torque', 0.1, 0.0, 100.0, 'N m',
              "each wheel's torque limit"),
    _physical('motor_deadband', 0.2, 0.0, 1000.0, 'rad/s',
              'slower wheel commands stay 0', allow_zero=True),
    _physical('max_wheel_speed', 20.0, 0.0, 1000.0, 'rad/s',
              "the motors' speed limit"),
    _physical('encoder_ticks', 508.8, 1.0, 1e7, '',
              "per revolution (an iRobot Create's)"),
)


def _as_given(spec):
    """``spec`` read without a check: the model checks the value against
    ``spec`` itself when it is made, and only if it is the model asked for.
    Its bounds stay for --help and the docs."""
    return spec._replace(check=raw)


#: The private parameters of one fake robot (fake_turtlebot.py; fake_fleet.py
#: applies them to every robot).
PARAMS = TOPIC_PARAMS + tuple(_as_given(spec) for spec in
                              DIFF_DRIVE_PARAMS + PHYSICS_PARAMS)

#: fake_fleet.py's own parameter: one robot per namespace.
ROBOTS = param('robots', ['robot1', 'robot2'], names, '',
               'namespaces, one robot each (topics, frames and tf in it)',
               maximum=MAX_ROBOTS)


def declared_fields(specs):
    """Class decorator: the dataclass whose fields (beyond its bases') are
    the parameters ``specs``, in order, each defaulting to its declared
    default; ``cls.PARAMS`` is then every field's declaration."""
    def make(cls):
        cls.__annotations__ = {spec.name: Any for spec in specs}
        for spec in specs:
            setattr(cls, spec.name, spec.default)
        cls.PARAMS = getattr(cls, 'PARAMS', ()) + tuple(specs)
        return dataclass(cls)
    return make
