#!/usr/bin/env python3
"""A drop-in for robot_pose_ekf: fuse wheel odometry, a gyro, visual
odometry and GPS into one planar pose.

Subscribes ``odom`` (nav_msgs/Odometry), ``imu_data`` (sensor_msgs/Imu),
``vo`` (nav_msgs/Odometry) and ``gps`` (nav_msgs/Odometry), each only when
used; publishes ``~odom_combined`` (geometry_msgs/PoseWithCovarianceStamped)
and, unless ``~publish_tf`` is false, the tf ``output_frame ->
base_footprint_frame``. Service ``~get_status`` (std_srvs/Trigger): the
filter's state, each sensor's, and the covariance, in ``message``. The
filter lives in ``rbx1_nav.estimation``; this node converts messages, keeps
time and watches for problems:

* a used sensor with no message ``sensor_timeout`` after start-up gets one
  warning naming its (remapped) topic and who publishes it;
* another node publishing the same transform on tf gets an error naming
  it and the fix, repeated every 30 s while it lasts.

The parameters have robot_pose_ekf's names and defaults, plus ~publish_tf
(false runs pose_ekf as an estimator only), ~gps_kalman and
~gps_frame_rotation. A sensor silent
for ~sensor_timeout is left out of the fusion and taken back when it
returns. The IMU's yaw is used as is: mount it with its z axis up. A sensor
variance of 1e5 or more, -1 or inf means "not measured": that component is
not fused (said once at info level). Without GPS the output frame starts at
the first odometry pose, known exactly. With ~gps_used, as robot_pose_ekf:
the filter starts at a GPS fix with the IMU's heading (the output frame is
the GPS frame, the IMU's yaw its heading), steps at the oldest of its
sensors' newest stamps (read off the stamps ~freq times a second, so the
answer does not depend on when messages arrive), takes the IMU's yaw as
absolute while GPS is active and the fixes on x, y only. With
~gps_frame_rotation the IMU's heading is only the prior of the heading in
the GPS frame: the rotation between the two is estimated from the fixes
as the robot moves. A bad
parameter is logged and the node exits with status 1. Unstamped,
out-of-order, repeated, NaN or absurd sensor messages and negative
variances are dropped (rbx1_nav.estimation.input_check), with one warning per sensor
and kind every 10 s that counts them, so the output's stamps only move
forward. Should the estimate ever stop being finite the filter restarts
instead of publishing it; should ROS time move backwards (a bag looping,
a simulator restarted) it says so and restarts from the next readings.
Should the ROS master restart, the node says so within a few seconds and
registers its topics, tf and service with the new master, so RViz and new
nodes find them again (rbx1_nav.common.master_ros); its connections go on.
"""
import signal

signal.signal(signal.SIGINT, signal.SIG_DFL)  # a signal during the imports: gone, quietly

from rbx1_nav.common import params  # noqa: E402
from rbx1_nav.common.node_ros import exit_node  # noqa: E402
from rbx1_nav.estimation.pose_ekf_ros import main  # noqa: E402

NAME = 'pose_ekf'
MIN_FREQ, MAX_FREQ = 0.01, 1000.0  # Hz, bounds of ~freq

PARAMS = (
    params.param('output_frame', 'odom', params.frame, '',
                 'parent frame of the fused pose and its tf'),
    params.param('base_footprint_frame', 'base_footprint', params.frame, '',
                 'child frame of the tf'),
    params.param('freq', 30.0, params.number, 'Hz', 'filter steps per second',
                 minimum=MIN_FREQ, maximum=MAX_FREQ),
    params.param('sensor_timeout', 1.0, params.number, 's',
                 'silence before a sensor is left out', minimum=0.0,
                 allow_zero=False),
    params.param('odom_used', True, params.flag, '', 'fuse odom'),
    params.param('imu_used', True, params.flag, '', 'fuse imu_data (yaw)'),
    params.param('vo_used', False, params.flag, '', 'fuse vo (relative pose)'),
    params.param('gps_used', False, params.flag, '',
                 'fuse gps (x, y) as robot_pose_ekf: start at the fix and '
                 'the IMU heading, output in the GPS frame'),
    params.param('gps_kalman', False, params.flag, '',
                 'with gps_used: fuse each fix once with its covariance '
                 '(Kalman gain) instead of robot_pose_ekf\'s per-step weight'),
    params.param('gps_frame_rotation', False, params.flag, '',
                 'with gps_used: estimate the rotation between the GPS frame '
                 'and the IMU\'s heading instead of taking the IMU\'s heading '
                 'as true in it (fixes fused as with gps_kalman)'),
    params.param('gps_frame_rotation_sd', 30.0, params.number, 'deg',
                 'with gps_frame_rotation: the prior standard deviation of '
                 'that rotation', minimum=0.0, maximum=180.0,
                 allow_zero=False),
    params.param('publish_tf', True, params.flag, '',
                 'publish tf output_frame -> base_footprint_frame'),
)


if __name__ == '__main__':
    exit_node(NAME, main(PARAMS, __doc__))
