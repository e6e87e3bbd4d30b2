"""Planar pose filter, everything behind ``pose_ekf.py`` (robot_pose_ekf's
job) but the ROS wiring, in four pieces each read on its own:

* :mod:`~rbx1_nav.pose_ekf.ekf`: the filter maths, an extended Kalman
  filter over ``(x, y, yaw)`` driven by motion increments, with relative
  (gyro, visual odometry) and absolute (yaw, position) updates;
* :mod:`~rbx1_nav.pose_ekf.sensors`: the sensor bookkeeping, each
  sensor's checked readings, its "not measured" components, whether it is
  active, and start-up;
* :mod:`~rbx1_nav.pose_ekf.fusion`: :class:`GyroOdomFusion`, when the
  filter starts, steps and restarts and which sensor does what in it (with
  and without robot_pose_ekf's GPS mode);
* :mod:`~rbx1_nav.pose_ekf.status`: the texts for a person, the status,
  a silent sensor's warning, a second publisher of our transform.

The names the node and the tests use are importable from here. No rospy:
times are float seconds, poses are plain tuples.
"""
from rbx1_nav.input_check import MAX_POSITION, MAX_VARIANCE
from rbx1_nav.pose_ekf.ekf import (MIN_VARIANCE, PlanarEkf, covariance_6x6,
                                   floored, is_finite_estimate,
                                   odom_increment, pose_covariance_3x3,
                                   position_covariance_2x2)
from rbx1_nav.pose_ekf.fusion import GyroOdomFusion
from rbx1_nav.pose_ekf.sensors import (SENSORS, UNMEASURED_VARIANCE,
                                       SensorWatch, unmeasured_components)
from rbx1_nav.pose_ekf.status import (OtherPublisherWatch,
                                      other_publisher_text,
                                      silent_sensor_text)

__all__ = ['PlanarEkf', 'SensorWatch', 'GyroOdomFusion', 'odom_increment',
           'floored', 'pose_covariance_3x3', 'position_covariance_2x2',
           'covariance_6x6', 'is_finite_estimate', 'silent_sensor_text',
           'OtherPublisherWatch', 'other_publisher_text', 'SENSORS',
           'MIN_VARIANCE', 'MAX_VARIANCE', 'MAX_POSITION',
           'UNMEASURED_VARIANCE', 'unmeasured_components']
