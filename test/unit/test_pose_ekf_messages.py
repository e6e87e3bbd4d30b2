"""Unit tests for pose_ekf's message conversions
(rbx1_nav.estimation.pose_ekf) and the texts of its start-up line and
status output (rbx1_nav.estimation.status); no ROS master needed."""
import math

import numpy as np
import pytest

geometry_msgs = pytest.importorskip('geometry_msgs.msg')
nav_msgs = pytest.importorskip('nav_msgs.msg')
sensor_msgs = pytest.importorskip('sensor_msgs.msg')
genpy = pytest.importorskip('genpy')

from rbx1_nav.estimation.ekf import covariance_6x6  # noqa: E402
from rbx1_nav.estimation.input_check import (BAD_ORIENTATION,  # noqa: E402
                                             InputCheck, RejectedInput)
from rbx1_nav.estimation.pose_ekf import (TOPICS, gps_fix, imu_yaw,  # noqa: E402
                                          planar_pose, pose_message,
                                          transform_message)
from rbx1_nav.estimation.sensors import SENSORS  # noqa: E402
from rbx1_nav.estimation.status import listening_text, output_text  # noqa: E402
from rbx1_nav.transform_utils import quat_to_angle  # noqa: E402

COV36 = [0.01 * i + 0.001 for i in range(36)]


def odometry(x=1.0, y=2.0, yaw=0.5, z=3.0, cov=COV36):
    msg = nav_msgs.Odometry()
    msg.pose.pose.position.x, msg.pose.pose.position.y = x, y
    msg.pose.pose.position.z = z
    msg.pose.pose.orientation.z = math.sin(yaw / 2.0)
    msg.pose.pose.orientation.w = math.cos(yaw / 2.0)
    msg.pose.covariance = cov
    return msg


def imu(yaw=-0.7, cov0=0.02, var=0.05):
    msg = sensor_msgs.Imu()
    msg.orientation.z = math.sin(yaw / 2.0)
    msg.orientation.w = math.cos(yaw / 2.0)
    msg.orientation_covariance = [cov0, 0, 0, 0, 0.03, 0, 0, 0, var]
    return msg


def test_every_sensor_has_a_relative_topic_and_a_message_type():
    assert set(TOPICS) == set(SENSORS)
    assert TOPICS['imu'] == ('imu_data', sensor_msgs.Imu)
    for name in ('odom', 'vo', 'gps'):
        assert TOPICS[name] == (name, nav_msgs.Odometry)


def test_planar_pose_takes_x_y_yaw_and_their_covariance():
    pose, cov = planar_pose(InputCheck(), 'odom', odometry())
    assert pose == pytest.approx((1.0, 2.0, 0.5))
    c = np.reshape(COV36, (6, 6))
    assert np.allclose(cov, c[np.ix_((0, 1, 5), (0, 1, 5))])


def test_a_quaternion_without_a_yaw_is_counted_and_rejected():
    inputs = InputCheck()
    msg = odometry()
    msg.pose.pose.orientation.z = msg.pose.pose.orientation.w = 0.0
    with pytest.raises(RejectedInput) as err:
        planar_pose(inputs, 'vo', msg)
    assert (err.value.sensor, err.value.kind) == ('vo', BAD_ORIENTATION)
    assert inputs.dropped('vo', BAD_ORIENTATION) == 1


def test_imu_yaw_and_its_variance():
    yaw, var = imu_yaw(InputCheck(), 'imu', imu())
    assert yaw == pytest.approx(-0.7)
    assert var == 0.05


def test_an_imu_without_orientation_is_counted_and_rejected():
    inputs = InputCheck()
    with pytest.raises(RejectedInput) as err:
        imu_yaw(inputs, 'imu', imu(cov0=-1.0))
    assert err.value.kind == BAD_ORIENTATION
    assert 'gives no orientation' in err.value.detail
    assert inputs.dropped('imu', BAD_ORIENTATION) == 1


def test_gps_fix_takes_x_y_and_ignores_z_and_the_orientation():
    msg = odometry()
    msg.pose.pose.orientation.w = 0.0  # no yaw: not needed for a fix
    fix, cov = gps_fix(InputCheck(), 'gps', msg)
    assert fix == (1.0, 2.0)
    assert np.allclose(cov, [[COV36[0], COV36[1]], [COV36[6], COV36[7]]])


def test_the_estimate_as_pose_and_transform():
    cov3 = np.array([[0.1, 0.01, 0.02], [0.01, 0.2, 0.03], [0.02, 0.03, 0.3]])
    stamp = genpy.Time.from_sec(12.5)
    msg = pose_message(stamp, 'odom', (3.0, -4.0, 2.0), cov3)
    assert msg.header.stamp == stamp and msg.header.frame_id == 'odom'
    position = msg.pose.pose.position
    assert (position.x, position.y, position.z) == (3.0, -4.0, 0.0)
    assert quat_to_angle(msg.pose.pose.orientation) == pytest.approx(2.0)
    assert list(msg.pose.covariance) == list(covariance_6x6(cov3))
    tf = transform_message(msg, 'base_footprint')
    assert tf.header == msg.header and tf.child_frame_id == 'base_footprint'
    assert (tf.transform.translation.x, tf.transform.translation.y,
            tf.transform.translation.z) == (3.0, -4.0, 0.0)
    assert tf.transform.rotation == msg.pose.pose.orientation


def test_the_start_up_line_names_the_topics_and_the_tf():
    topics = {'odom': '/odom', 'imu': '/imu_data'}
    assert listening_text(topics, '/robot_pose_ekf/odom_combined', 'odom',
                          'base_footprint', True) == (
        'listening on imu /imu_data, odom /odom; publishing '
        '/robot_pose_ekf/odom_combined and tf odom -> base_footprint')
    assert listening_text(topics, '/e/odom_combined', 'odom', 'base', False) == (
        'listening on imu /imu_data, odom /odom; publishing /e/odom_combined '
        'only (~publish_tf false: no tf)')


def test_the_status_output_lines():
    assert output_text('/e/odom_combined', 'odom', 'base_footprint', True,
                       []) == 'output: /e/odom_combined, tf odom -> base_footprint'
    assert output_text('/e/odom_combined', 'odom', 'base_footprint', False,
                       []) == 'output: /e/odom_combined, tf off (~publish_tf false)'
    assert output_text('/e/odom_combined', 'odom', 'base_footprint', True,
                       ['/a', '/b']) == (
        'output: /e/odom_combined, tf odom -> base_footprint\n'
        'also publishing base_footprint on tf: /a, /b')
