"""The fake robot's parameters, declared once for
nodes/fake_turtlebot.py (one robot) and nodes/fake_fleet.py (every robot
of a fleet takes the same values). The topics are in
rbx1_nav.sim.robot_ros, the motion model in rbx1_nav.sim.diff_drive. No rospy
here.
"""
from rbx1_nav.sim.diff_drive import DEFAULT_COVARIANCE_DIAGONAL, DiffDriveConfig
from rbx1_nav.sim.physics import PhysicsConfig
from rbx1_nav.common.params import (POSITIVE, flag, frame, names, number, number_list,
                             param, raw, text)

__all__ = ['PARAMS', 'ROBOTS', 'config_class', 'MAX_ROBOTS', 'WARN_PERIOD', 'MAX_CATCH_UP',
           'MIN_RATE', 'MAX_RATE', 'GPS_UNKNOWN_VARIANCE']

WARN_PERIOD = 5.0  # s between repeats of the same warning
MAX_CATCH_UP = 1.0  # s of ROS time the loop replays step by step when late
# Bounds of ~rate (Hz): the loop steps every 1/~rate s of ROS time, so a
# huge rate would be a zero period (an endless catch-up) and a tiny one a
# sleep too long for the OS.
MIN_RATE, MAX_RATE = 0.01, 1000.0
MAX_GPS_NOISE = 1000.0  # m, bound of ~gps_noise
GPS_UNKNOWN_VARIANCE = 1e6  # reported for z and the orientation (not measured)
MAX_ROBOTS = 1000  # bound of the length of fake_fleet's ~robots


COVARIANCE = dict(length=6, **POSITIVE)
#: The private parameters of one fake robot (fake_turtlebot.py; fake_fleet.py
#: applies them to every robot).
PARAMS = (
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
) + tuple(param(name, getattr(DiffDriveConfig, name), raw, '',
                'model setting, checked by rbx1_nav.sim.diff_drive')
          for name in DiffDriveConfig.names()) + tuple(
    param(name, getattr(PhysicsConfig, name), raw, '',
          'physics robot setting, checked by rbx1_nav.sim.physics')
    for name in PhysicsConfig.names() if name not in DiffDriveConfig.names())


def config_class(values):
    """The model configuration the checked ``values`` ask for: PhysicsConfig
    with ~physics, else DiffDriveConfig."""
    return PhysicsConfig if values['physics'] else DiffDriveConfig

#: fake_fleet.py's own parameter: one robot per namespace.
ROBOTS = param('robots', ['robot1', 'robot2'], names, '',
               'namespaces, one robot each (topics, frames and tf in it)',
               maximum=MAX_ROBOTS)
