"""Unit tests for pose_ekf's visual odometry and GPS inputs, its status
text, its start-up sensor check and its second-publisher watch
(rbx1_nav.estimation; the gyro + wheel basics are in test_pose_ekf.py)."""
import math

import numpy as np
import pytest

from rbx1_nav.estimation.ekf import PlanarEkf, odom_increment, position_covariance_2x2
from rbx1_nav.estimation.fusion import GyroOdomFusion
from rbx1_nav.estimation.status import (OtherPublisherWatch, other_publisher_text,
                                        silent_sensor_text)
from rbx1_nav.transform_utils import normalize_angle

# Per 30 Hz step. x, y: a random walk of 0.055 m/sqrt(s), about what it
# takes to cover the wheels' 3 % scale error at 0.3 m/s; poor yaw.
ODOM_COV = np.diag([1e-4, 1e-4, 1e-2])
VO_COV = np.diag([1e-6, 1e-6, 1e-4])
GYRO_VAR = 1e-5


def compose(pose, inc):
    x, y, yaw = pose
    c, s = math.cos(yaw), math.sin(yaw)
    return (x + c * inc[0] - s * inc[1], y + s * inc[0] + c * inc[1],
            normalize_angle(yaw + inc[2]))


class Robot(object):
    """A scripted robot: wheels that read distance ``linear_scale`` too long,
    a perfect gyro, visual odometry and a GPS (truth + white noise) in a
    frame whose origin is ``gps_origin`` in the output frame."""

    def __init__(self, fusion, linear_scale=1.0, rate=30.0, gps_sd=0.3,
                 gps_var=None, gps_rate=1.0, gps_origin=(0.0, 0.0), seed=1):
        self.fusion = fusion
        self.truth = self.odom = self.vo = (0.0, 0.0, 0.0)
        self.vo_zero = (5.0, -3.0, 1.0)  # visual odometry's own start
        self.gyro_yaw = 1.0
        self.linear_scale = linear_scale
        self.dt, self.t = 1.0 / rate, 0.0
        self.gps_sd = gps_sd
        self.gps_var = gps_sd ** 2 if gps_var is None else gps_var
        self.gps_every = int(round(rate / gps_rate))
        self.gps_origin = gps_origin
        self.rng = np.random.default_rng(seed)
        self.k = 0
        self.events = []

    def vo_pose(self):
        return compose(self.vo_zero, self.truth)

    def run(self, seconds, v=0.0, w=0.0, odom=True, imu=True, vo=False,
            gps=False):
        for _ in range(int(round(seconds / self.dt))):
            self.t += self.dt
            self.k += 1
            inc = (v * self.dt, 0.0, w * self.dt)
            self.truth = compose(self.truth, inc)
            self.odom = compose(self.odom, (inc[0] * self.linear_scale, 0.0,
                                            inc[2]))
            self.gyro_yaw = normalize_angle(self.gyro_yaw + inc[2])
            f = self.fusion
            if odom:
                f.add_odom(self.t, self.t, self.odom, ODOM_COV)
            if imu:
                f.add_imu(self.t, self.t, self.gyro_yaw, GYRO_VAR)
            if vo:
                f.add_vo(self.t, self.t, self.vo_pose(), VO_COV)
            if gps and self.k % self.gps_every == 0:
                noise = self.rng.normal(0.0, self.gps_sd, 2)
                f.add_gps(self.t, self.t,
                          (self.truth[0] - self.gps_origin[0] + noise[0],
                           self.truth[1] - self.gps_origin[1] + noise[1]),
                          np.eye(2) * self.gps_var)
            self.events += f.step(self.t)

    def zigzag(self, legs=10, gps=True, **sensors):
        """``legs`` legs of 2 m, turning +90 and -90 deg in turn: 20 m of
        travel ending about 14 m from the start."""
        for leg in range(legs):
            self.run(2.0 / 0.3, v=0.3, gps=gps, **sensors)
            self.run(math.pi / 2, w=0.5 if leg % 2 == 0 else -0.5, gps=gps,
                     **sensors)

    def position_error(self):
        _, (x, y, _), _ = self.fusion.estimate
        return math.hypot(x - self.truth[0], y - self.truth[1])


# --- GPS (robot_pose_ekf's mode: the output frame is the GPS frame) --------

def gps_robot(gps_kalman=False, **options):
    """A robot whose IMU heading is the truth's: the GPS frame's, as a
    compass gives it."""
    robot = Robot(GyroOdomFusion(gps_used=True, gps_kalman=gps_kalman,
                                 sensor_timeout=options.pop('timeout', 1.5)),
                  linear_scale=1.03, **options)
    robot.gyro_yaw = 0.0
    return robot


@pytest.mark.parametrize('gps_kalman', [False, True])
def test_gps_pulls_drifting_odometry_back(gps_kalman):
    raw = Robot(GyroOdomFusion(), linear_scale=1.03)
    fused = gps_robot(gps_kalman)
    raw.zigzag(gps=False)
    fused.zigzag(gps=True)
    raw_error, fused_error = raw.position_error(), fused.position_error()
    assert raw_error > 0.3  # 3 % of about 14 m of net displacement
    cov = fused.fusion.estimate[2]
    # Within three standard deviations of its own covariance.
    assert fused_error < 3.0 * math.sqrt(cov[0, 0] + cov[1, 1])
    # robot_pose_ekf's weight per step (here one a fix) pulls gently: it
    # is mostly the odometry's track from the first fix. The Kalman gain
    # weighs each fix against the odometry's accumulated drift.
    assert fused_error < (0.35 * raw_error if gps_kalman else 1.0)


def test_gps_starts_at_the_fix_with_the_imu_heading():
    robot = gps_robot(True, gps_origin=(-1000.0, 250.0))  # fixes (1000, -250)
    robot.run(0.5, gps=True)
    assert robot.fusion.estimate is None  # no fix yet (1 Hz)
    robot.run(1.0, gps=True)
    assert any('filter started at the GPS fix' in t for _, t in robot.events)
    robot.zigzag()
    robot.run(2.0, gps=True)  # at rest: the estimate's stamp is a fix's
    x, y, yaw = robot.fusion.estimate[1]
    assert math.hypot(x - robot.truth[0] - 1000.0,
                      y - robot.truth[1] + 250.0) < 0.3
    assert yaw == pytest.approx(robot.truth[2], abs=1e-3)


def test_gps_start_does_not_change_the_answer_with_gps_kalman():
    ends = []
    for late in (0.0, 2.0, 4.0):
        robot = gps_robot(gps_kalman=True)
        robot.run(late, odom=False, imu=False, gps=False)
        robot.zigzag()
        ends.append(robot.fusion.estimate[1])
    for end in ends[1:]:
        assert end == pytest.approx(ends[0], abs=0.01)


def test_gps_with_a_huge_covariance_is_not_measured():
    robot = gps_robot(gps_var=1e8)
    robot.zigzag(legs=1)
    assert robot.fusion.estimate is None  # no position to start from
    assert any('variance 1e+08, 1e+08 of x, y means "not measured"' in t
               for _, t in robot.events)


def test_gps_dropped_and_taken_back():
    robot = gps_robot(gps_kalman=True)
    robot.zigzag(legs=4)
    robot.zigzag(legs=2, gps=False)
    assert any('gps timed out' in t for _, t in robot.events)
    assert 'dropped: gps' in robot.fusion.state()
    robot.zigzag(legs=4)
    assert any('gps is back' in t for _, t in robot.events)
    assert robot.position_error() < 0.25


def test_a_gps_jump_is_dropped_with_a_warning():
    robot = gps_robot(gps_kalman=True)
    robot.zigzag(legs=2)
    robot.run(2.0, gps=True)  # at rest
    before = robot.fusion.estimate[1]
    robot.gps_origin = (-5000.0, 0.0)  # the fixes jump 5 km
    robot.run(3.0, gps=True)
    warnings = [t for lvl, t in robot.events if lvl == 'warn']
    assert any('dropped gps on gps: jump' in t for t in warnings)
    assert robot.fusion.estimate[1] == pytest.approx(before, abs=1e-3)


@pytest.mark.parametrize('bad', [(float('nan'), 0.0), (0.0, float('inf')),
                                 (2e9, 0.0)])
def test_unusable_gps_fixes_are_rejected(bad):
    fusion = GyroOdomFusion(gps_used=True)
    with pytest.raises(ValueError):
        fusion.add_gps(1.0, 1.0, bad, np.eye(2))
    with pytest.raises(ValueError, match='not finite'):
        fusion.add_gps(1.0, 1.0, (0.0, 0.0), np.eye(2) * float('nan'))
    with pytest.raises(ValueError, match='zero variance'):
        fusion.add_gps(1.0, 1.0, (0.0, 0.0), np.zeros((2, 2)))
    with pytest.raises(ValueError, match='another clock'):
        fusion.add_gps(1.0, 1e9, (0.0, 0.0), np.eye(2))
    with pytest.raises(ValueError, match='absurd'):
        fusion.add_gps(1.0, 1.0, (0.0, 0.0), [[1.0, 1e13], [1e13, 1.0]])


def test_position_covariance_block():
    cov36 = np.arange(36.0)
    assert np.array_equal(position_covariance_2x2(cov36), [[0, 1], [6, 7]])


def test_gps_is_ignored_when_not_used():
    robot = Robot(GyroOdomFusion(), linear_scale=1.03)
    robot.zigzag(legs=2, gps=True)
    assert robot.fusion.estimate[1][:2] == pytest.approx(robot.odom[:2],
                                                         abs=1e-6)


# --- visual odometry ---------------------------------------------------------

def test_vo_alone_works_like_odometry():
    robot = Robot(GyroOdomFusion(odom_used=False, imu_used=False,
                                 vo_used=True))
    robot.zigzag(gps=False, odom=False, imu=False, vo=True)
    # Started at the visual odometry's first pose, then followed its steps.
    assert robot.fusion.estimate[1] == pytest.approx(robot.vo_pose(), abs=1e-9)
    assert any('first visual odometry pose' in t for _, t in robot.events)


def test_vo_with_odometry_corrects_the_wheels():
    wheels = Robot(GyroOdomFusion(imu_used=False), linear_scale=1.03)
    both = Robot(GyroOdomFusion(imu_used=False, vo_used=True),
                 linear_scale=1.03)
    wheels.zigzag(gps=False, imu=False)
    both.zigzag(gps=False, imu=False, vo=True)
    # Visual odometry is 100x more certain in yaw and as good in x, y: the
    # fused track stays much closer to the truth than the wheels alone.
    assert both.position_error() < 0.6 * wheels.position_error()
    # Its increments (relative to its own start (5, -3, 1)) were used, not
    # its absolute pose.
    assert math.hypot(*both.fusion.estimate[1][:2]) < 20.0


def test_vo_taking_over_when_odometry_stops_and_handing_back():
    robot = Robot(GyroOdomFusion(vo_used=True, sensor_timeout=0.5),
                  linear_scale=1.0)
    robot.run(2.0, v=0.3, vo=True)
    robot.run(3.0, v=0.3, w=0.2, odom=False, vo=True)
    assert any('odom timed out' in t for _, t in robot.events)
    robot.odom = (50.0, 50.0, 0.0)  # odometry restarts somewhere else
    robot.run(3.0, v=0.3, vo=True)
    assert any('odom is back' in t for _, t in robot.events)
    assert robot.position_error() < 0.02
    assert abs(normalize_angle(robot.fusion.estimate[1][2]
                               - robot.truth[2])) < 0.01


def test_pose_increment_update_is_the_weighted_mean_of_both_increments():
    ekf = PlanarEkf((1.0, 2.0, 0.5), np.eye(3) * 1e-9, anchors=('vo',))
    ekf.predict((0.2, 0.0, 0.1), np.diag([1e-2, 1e-2, 1e-2]))
    ekf.update_pose_increment((0.1, 0.0, 0.05), np.diag([1e-2, 1e-2, 1e-2]))
    got = odom_increment((1.0, 2.0, 0.5), ekf.pose)
    assert got == pytest.approx((0.15, 0.0, 0.075), abs=2e-3)
    assert ekf.cov[0, 0] == pytest.approx(0.005, rel=0.05)


# --- status and start-up check -----------------------------------------------

def test_status_text_names_the_state_sensors_and_covariance():
    fusion = GyroOdomFusion(gps_used=True, sensor_timeout=1.5)
    fusion.step(0.0)
    text = fusion.status_text(0.0, {'odom': '/odom', 'imu': '/imu_data'})
    assert text.startswith('state: waiting for imu and gps')
    assert 'odom on /odom (wheel odometry, relative pose): waiting' in text
    assert 'vo: not used' in text and 'estimate: none yet' in text
    robot = Robot(fusion)
    robot.run(2.0, v=0.3, gps=True)
    text = fusion.status_text(robot.t)
    assert text.startswith('state: running\n')
    assert ('gps (absolute x, y in the output frame): active, last stamp '
            '2.000') in text
    assert 'covariance (x, y, yaw): [' in text
    robot.run(2.0, v=0.3, imu=False, gps=True)
    assert fusion.state() == 'running; dropped: imu'


def test_silent_sensors_are_reported_once_after_the_timeout():
    fusion = GyroOdomFusion(sensor_timeout=1.0, gps_used=True)
    fusion.step(10.0)
    fusion.add_odom(10.2, 10.2, (0.0, 0.0, 0.0), ODOM_COV)
    fusion.step(10.2)
    assert fusion.silent_sensors(10.9) == []
    assert fusion.silent_sensors(11.0) == ['imu', 'gps']
    assert fusion.silent_sensors(12.0) == []
    assert fusion.state() == ('waiting for imu and gps to start (no data yet '
                              'from: imu, gps)')


def test_silent_sensor_text_says_who_publishes():
    none = silent_sensor_text('imu', '/robot/gyro', 1.0, [])
    assert 'no message came on /robot/gyro within 1 s' in none
    assert 'nothing publishes /robot/gyro' in none
    some = silent_sensor_text('gps', '/gps', 2.0, ['/b', '/a'])
    assert '/a, /b publishes it but sent nothing' in some
    assert 'whether anything publishes it is unknown' in silent_sensor_text(
        'vo', '/vo', 1, None)


def test_silent_sensor_text_says_when_all_that_came_was_dropped():
    """A driver publishing NaN did send: its readings were all dropped."""
    from rbx1_nav.estimation.input_check import BAD_ORIENTATION, RejectedInput
    last = RejectedInput('odom', BAD_ORIENTATION, 'quaternion has a non-finite component: '
                         '(0.0, 0.0, nan, nan)')
    text = silent_sensor_text('odom', '/odom', 1.0, ['/nan_driver'], (25, last))
    assert text == ('odom_used is true but every reading on /odom in the 1 s since start-up '
                    'was dropped (25 so far, the last as bad orientation: quaternion has a '
                    'non-finite component: (0.0, 0.0, nan, nan)): fix /nan_driver, which '
                    'publishes it')
    assert 'sent nothing' not in text
    assert silent_sensor_text('odom', '/odom', 1.0, None, (1, last)).endswith(
        'fix the node that publishes it')


# --- a second publisher of the transform -------------------------------------

def test_other_publisher_reported_at_once_then_every_period():
    watch = OtherPublisherWatch(period=30.0, quiet=5.0)
    reports = [t for t in np.arange(0.0, 70.0, 0.02)
               if watch.seen('/fake_turtlebot', float(t))]
    assert reports == pytest.approx([0.0, 30.0, 60.0], abs=0.021)
    assert watch.publishers == ['/fake_turtlebot']
    assert watch.gone(72.0) == [] and watch.gone(75.1) == ['/fake_turtlebot']
    assert watch.seen('/fake_turtlebot', 80.0)  # back: reported again at once


def test_other_publisher_text_names_node_and_fixes():
    text = other_publisher_text('/fake_turtlebot', 'odom', 'base_footprint',
                                '/tf')
    assert text.startswith('node /fake_turtlebot also publishes the '
                           'transform odom -> base_footprint on /tf')
    assert 'publish_tf: false' in text and '~publish_tf false' in text


def test_start_up_can_be_marked_before_the_first_step():
    fusion = GyroOdomFusion(True, True, 2.0)
    fusion.start(10.0)
    fusion.step(11.0)
    fusion.start(11.0)  # the first mark stands
    assert fusion.silent_sensors(11.9) == []
    assert fusion.silent_sensors(12.0) == ['odom', 'imu']


@pytest.mark.parametrize('offset_deg', [-20.0, 35.0])
def test_gps_frame_rotation_finds_an_imu_heading_off_the_gps_frame(
        offset_deg):
    """An IMU whose heading is ``offset_deg`` off the GPS frame's (a
    compass beside a motor, a gyro's own zero): robot_pose_ekf's mode takes
    it as true and keeps the error; with gps_frame_rotation the fixes of a
    20 m zigzag find the rotation, and the heading, within 2 deg."""
    offset = math.radians(offset_deg)
    ends = {}
    for rotation_sd in (None, math.radians(30.0)):
        robot = Robot(GyroOdomFusion(gps_used=True, sensor_timeout=1.5,
                                     gps_frame_rotation=rotation_sd),
                      linear_scale=1.03)
        robot.gyro_yaw = -offset
        robot.zigzag()
        robot.run(2.0, gps=True)  # at rest: the estimate's stamp is a fix's
        ends[rotation_sd] = robot
    kept = ends[None]
    assert abs(normalize_angle(kept.fusion.estimate[1][2] - kept.truth[2])
               ) == pytest.approx(abs(offset), abs=math.radians(1.0))
    found = ends[math.radians(30.0)]
    yaw_error = normalize_angle(found.fusion.estimate[1][2] - found.truth[2])
    assert abs(yaw_error) < math.radians(2.0)
    rotation, variance = found.fusion.ekf.rotation
    assert rotation == pytest.approx(offset, abs=math.radians(2.0))
    assert math.sqrt(variance) < math.radians(2.0)  # and it knows it
    assert found.position_error() < 0.5 * kept.position_error()
    assert 'GPS frame rotation' in found.fusion.status_text(found.t)


def test_gps_frame_rotation_needs_a_positive_prior():
    with pytest.raises(ValueError, match='gps_frame_rotation'):
        GyroOdomFusion(gps_used=True, gps_frame_rotation=0.0)


@pytest.mark.parametrize('gps_frame_rotation', [None, math.radians(30.0)])
def test_gps_mode_survives_every_sensor_lost_and_back(gps_frame_rotation):
    """A driver that dies and comes back: every sensor silent (dropped
    after 5 sensor timeouts of all-round silence), then back: the filter
    re-bases them and goes on, the returning odometry included."""
    robot = Robot(GyroOdomFusion(gps_used=True, sensor_timeout=1.5,
                                 gps_frame_rotation=gps_frame_rotation),
                  linear_scale=1.03)
    robot.gyro_yaw = 0.0
    robot.zigzag(legs=2)
    robot.run(5.0, odom=False, imu=False, gps=False)
    assert not any('timed out' in t for _, t in robot.events)
    robot.run(3.0, odom=False, imu=False, gps=False)
    assert 'dropped: odom, imu, gps' in robot.fusion.state()
    robot.zigzag(legs=4)
    robot.run(2.0, gps=True)
    assert any('odom is back' in t for _, t in robot.events)
    assert robot.fusion.state() == 'running'
    # As test_gps_pulls_drifting_odometry_back: robot_pose_ekf's weight
    # pulls gently, the Kalman gain (with gps_frame_rotation) harder.
    assert robot.position_error() < (1.0 if gps_frame_rotation is None
                                     else 0.35)
