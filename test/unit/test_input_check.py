"""Unit tests for rbx1_nav.estimation.input_check: the input screening shared by
pose_ekf and odom_ekf (no ROS master needed)."""
import numpy as np
import pytest

from rbx1_nav.estimation.input_check import (ABSURD, DUPLICATE, MAX_POSITION, MAX_VARIANCE,
                                             NEGATIVE_VARIANCE, NOT_FINITE, OUT_OF_ORDER,
                                             ZERO_STAMP, InputCheck, RejectedInput,
                                             source_text)
from rbx1_nav.common.ros_time import ClockWatch, time_moved_back_text

NAN, INF = float('nan'), float('inf')
COV = np.diag([0.01, 0.01, 0.1])


def rejection(check, *args, **values):
    with pytest.raises(RejectedInput) as caught:
        check.check(*args, **values)
    return caught.value


@pytest.mark.parametrize('values,kind,shown', [
    (dict(position=(NAN, 0.0)), NOT_FINITE, 'nan'),
    (dict(position=(0.0, -INF)), NOT_FINITE, 'inf'),
    (dict(angles=(NAN,)), NOT_FINITE, 'nan'),
    (dict(covariance=np.diag([0.01, NAN, 0.1])), NOT_FINITE, 'nan'),
    (dict(position=(1e300, 0.0)), ABSURD, '1e+300'),
    (dict(position=(0.0, -MAX_POSITION * 1.01)), ABSURD, '-1.01e+08'),
    (dict(covariance=np.diag([0.01, 1e300, 0.1])), ABSURD, '1e+300'),
    (dict(covariance=np.diag([0.01, -0.5, 0.1])), NEGATIVE_VARIANCE, '-0.5'),
    (dict(covariance=[[-1e-9]]), NEGATIVE_VARIANCE, '-1e-09'),
])
def test_each_bad_value_is_rejected_with_its_kind_and_value(values, kind,
                                                            shown):
    check = InputCheck()
    err = rejection(check, 'odom', 5.0, **values)
    assert (err.sensor, err.kind) == ('odom', kind)
    assert shown in err.detail
    assert isinstance(err, ValueError)
    assert check.newest('odom') is None  # nothing taken
    check.check('odom', 5.0, position=(1.0, 2.0), angles=(0.5,),
                covariance=COV)
    assert check.newest('odom') == 5.0


def test_values_at_the_bounds_are_taken():
    check = InputCheck()
    check.check('gps', 1.0, position=(MAX_POSITION, -MAX_POSITION),
                covariance=np.full((2, 2), MAX_VARIANCE))
    check.check('imu', 1.0, angles=(1e300,), covariance=[[0.0]])
    assert check.newest('gps') == check.newest('imu') == 1.0


def test_stamps_must_move_forward_per_sensor():
    check = InputCheck()
    assert rejection(check, 'odom', 0.0).kind == ZERO_STAMP
    check.check('odom', 10.0)
    err = rejection(check, 'odom', 9.5)
    assert err.kind == OUT_OF_ORDER
    assert '9.500' in err.detail and '0.500 s older' in err.detail
    assert rejection(check, 'odom', 10.0).kind == DUPLICATE
    check.check('imu', 9.5)  # another sensor has its own order
    check.check('odom', 10.01)
    assert check.newest('odom') == 10.01 and check.newest('imu') == 9.5


def test_a_rejected_reading_does_not_move_the_newest_stamp():
    check = InputCheck()
    check.check('odom', 1.0)
    rejection(check, 'odom', 5.0, position=(NAN, 0.0))
    check.check('odom', 2.0)  # in order: the NaN reading was not taken
    assert check.newest('odom') == 2.0


def test_a_bad_value_is_reported_as_such_whatever_its_stamp():
    check = InputCheck()
    check.check('odom', 5.0)
    assert rejection(check, 'odom', 1.0, position=(1e300, 0.0)).kind == ABSURD
    assert rejection(check, 'odom', 0.0, angles=(NAN,)).kind == NOT_FINITE


def test_one_warning_per_sensor_and_kind_per_period_with_the_count():
    check = InputCheck(period=10.0)
    check.check('odom', 100.0)
    texts = []
    for k in range(1, 61):  # 6 s at 10 Hz: one reading 0.5 s late each
        now = 100.0 + 0.1 * k
        check.check('odom', now)
        err = rejection(check, 'odom', now - 0.5)
        texts.append(check.warning(err, now, 'odom on /odom'))
    warned = [t for t in texts if t]
    assert len(warned) == 1 and texts[0] == warned[0]
    assert warned[0].startswith('dropped odom on /odom: out of order: stamp '
                                '99.600 s is 0.500 s older')
    assert '(1 such reading dropped since the last warning' in warned[0]
    assert check.dropped('odom', OUT_OF_ORDER) == 59
    # Another sensor and another kind warn at once, each on its own.
    err = rejection(check, 'imu', 0.0)
    assert 'dropped imu: zero stamp' in check.warning(err, 106.0)
    err = rejection(check, 'odom', 106.0, position=(NAN, 0.0))
    assert check.warning(err, 106.0).startswith('dropped odom: not finite')
    # 10 s after the first, the next out-of-order warning counts them all.
    err = rejection(check, 'odom', 99.0)
    text = check.warning(err, 110.2)
    assert '(60 such readings dropped since the last warning' in text
    assert check.dropped('odom', OUT_OF_ORDER) == 0
    err = rejection(check, 'odom', 99.0)
    assert check.warning(err, 110.3) is None


def test_a_new_clock_forgets_the_stamps_and_warns_again():
    check = InputCheck()
    check.check('odom', 100.0)
    assert check.warning(rejection(check, 'odom', 90.0), 100.0)
    check.new_clock()
    check.check('odom', 90.0)  # the new clock's readings are taken
    assert check.newest('odom') == 90.0
    # Time moved back, so the throttle lets the next warning through.
    assert check.warning(rejection(check, 'odom', 89.0), 90.0)


def test_clock_watch_measures_each_move_back():
    clock = ClockWatch()
    assert clock.moved_back(5.0) == 0.0
    assert clock.moved_back(5.0) == 0.0
    assert clock.moved_back(7.5) == 0.0
    assert clock.moved_back(2.5) == pytest.approx(5.0)
    assert clock.moved_back(3.0) == 0.0  # from the new time on


def test_time_moved_back_text():
    assert time_moved_back_text(10.04) == (
        'ROS time moved backwards by 10.0 s: a bag looping or the simulator '
        'restarted? Restarting from the next readings')


def test_the_source_names_the_publishing_node_when_known():
    assert source_text('odom', '/odom', '/nan_driver') == 'odom on /odom from /nan_driver'
    assert source_text('odom', '/odom') == 'odom on /odom'
    check = InputCheck()
    err = rejection(check, 'odom', 1.0, position=(NAN, NAN))
    assert check.warning(err, 1.0, source_text('odom', '/odom', '/d')).startswith(
        'dropped odom on /odom from /d: not finite: position (nan, nan)')


def test_rejected_counts_every_drop_of_a_sensor_and_keeps_the_last():
    check = InputCheck()
    assert check.rejected('odom') is None
    rejection(check, 'odom', 1.0, position=(NAN, 0.0))
    check.warning(rejection(check, 'odom', 0.0), 1.0)  # a warning resets dropped(), not this
    count, last = check.rejected('odom')
    assert count == 2 and last.kind == ZERO_STAMP
    assert check.rejected('imu') is None
