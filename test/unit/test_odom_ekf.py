"""Unit tests for rbx1_nav.estimation.odom_ekf (no ROS master needed)."""
import copy
import math

import pytest

geometry_msgs = pytest.importorskip('geometry_msgs.msg')
rospy_time = pytest.importorskip('genpy')

from rbx1_nav.estimation.input_check import (ABSURD, DUPLICATE, MAX_POSITION, NEGATIVE_VARIANCE,  # noqa: E402
                                             NOT_FINITE, OUT_OF_ORDER, ZERO_STAMP, RejectedInput)
from rbx1_nav.estimation.odom_ekf import (MAX_TWIST, MIN_TWIST_DT,  # noqa: E402
                                          UNKNOWN_TWIST_COVARIANCE,
                                          UNKNOWN_VARIANCE, POSE_TYPE, PoseToOdometry,
                                          BOOK_INPUT, DEFAULT_INPUTS, FILTER_INPUT,
                                          SWITCH_AFTER, InputChoice,
                                          input_publishers, silent_input_text)
from rbx1_nav.transform_utils import strip_leading_slash  # noqa: E402


def make_pose(x=1.0, y=2.0, yaw=0.5, t=10.0, frame='odom', cov=None, seq=7):
    msg = geometry_msgs.PoseWithCovarianceStamped()
    msg.header.seq = seq
    msg.header.stamp = rospy_time.Time.from_sec(t)
    msg.header.frame_id = frame
    msg.pose.pose.position.x = x
    msg.pose.pose.position.y = y
    msg.pose.pose.position.z = 0.25
    msg.pose.pose.orientation.z = math.sin(yaw / 2.0)
    msg.pose.pose.orientation.w = math.cos(yaw / 2.0)
    msg.pose.covariance = cov if cov is not None else [
        0.1 * i + 0.001 for i in range(36)]
    return msg


def test_fields_map_one_to_one():
    msg = make_pose()
    odom = PoseToOdometry().convert(msg)
    assert odom.header.seq == 7
    assert odom.header.stamp == msg.header.stamp
    assert odom.header.frame_id == 'odom'
    assert odom.child_frame_id == 'base_footprint'
    assert odom.pose.pose == msg.pose.pose
    assert odom.pose.pose is not msg.pose.pose


def test_all_36_covariance_entries_copied_exactly():
    cov = [math.pi * (i - 17) ** 3 + 1e-300 for i in range(36)]
    for i in range(0, 36, 7):  # variances are not negative
        cov[i] = abs(cov[i])
    odom = PoseToOdometry().convert(make_pose(cov=tuple(cov)))
    assert list(odom.pose.covariance) == cov


@pytest.mark.parametrize('frame,expected', [
    ('/odom_combined', 'odom_combined'), ('//odom', 'odom'),
    ('odom', 'odom'), ('', 'odom')])
def test_frame_slash_stripped_and_default(frame, expected):
    assert PoseToOdometry().convert(make_pose(frame=frame)).header.frame_id \
        == expected


def test_frame_parameters_override_and_are_stripped():
    conv = PoseToOdometry(frame_id='/map', child_frame_id='/base_link')
    odom = conv.convert(make_pose(frame='odom_combined'))
    assert (odom.header.frame_id, odom.child_frame_id) == ('map', 'base_link')
    assert strip_leading_slash('/a/b') == 'a/b'


def test_input_is_not_mutated():
    msg = make_pose(frame='/odom', t=10.0)
    before = copy.deepcopy(msg)
    conv = PoseToOdometry(estimate_twist=True)
    conv.convert(make_pose(frame='/odom', x=0.0, t=9.0))
    conv.convert(msg)  # with a twist from the previous pose
    with pytest.raises(ValueError):
        conv.convert(msg)  # the same stamp again: dropped
    assert msg == before


@pytest.mark.parametrize('field', ['x', 'y', 'z'])
@pytest.mark.parametrize('bad', [float('nan'), float('inf')])
def test_non_finite_position_is_dropped(field, bad):
    msg = make_pose()
    setattr(msg.pose.pose.position, field, bad)
    with pytest.raises(ValueError, match='NaN or infinite'):
        PoseToOdometry().convert(msg)


def test_nan_orientation_covariance_and_zero_quaternion_are_dropped():
    conv = PoseToOdometry()
    msg = make_pose()
    msg.pose.pose.orientation.w = float('nan')
    with pytest.raises(ValueError):
        conv.convert(msg)
    msg = make_pose(cov=[0.0] * 35 + [float('nan')])
    with pytest.raises(ValueError, match='covariance'):
        conv.convert(msg)
    msg = make_pose()
    msg.pose.pose.orientation.z = msg.pose.pose.orientation.w = 0.0
    with pytest.raises(ValueError, match='quaternion'):
        conv.convert(msg)


def test_dropped_pose_does_not_break_the_twist_estimate():
    conv = PoseToOdometry()
    conv.convert(make_pose(x=0.0, y=0.0, yaw=0.0, t=1.0))
    bad = make_pose(x=float('nan'), t=1.5)
    with pytest.raises(ValueError):
        conv.convert(bad)
    odom = conv.convert(make_pose(x=1.0, y=0.0, yaw=0.0, t=2.0))
    assert odom.twist.twist.linear.x == pytest.approx(1.0)


def test_first_twist_is_zero_and_unknown():
    odom = PoseToOdometry().convert(make_pose())
    t = odom.twist.twist
    assert (t.linear.x, t.linear.y, t.angular.z) == (0.0, 0.0, 0.0)
    assert [odom.twist.covariance[7 * i] for i in range(6)] == \
        [UNKNOWN_VARIANCE] * 6


def test_twist_estimated_in_body_frame():
    conv = PoseToOdometry(twist_variance=0.02)
    # Heading +90 degrees, moving +y in the odom frame = forward in the body.
    conv.convert(make_pose(x=0.0, y=0.0, yaw=math.pi / 2, t=1.0))
    odom = conv.convert(make_pose(x=0.0, y=0.5, yaw=math.pi / 2 + 0.2, t=1.5))
    t = odom.twist.twist
    assert t.linear.x == pytest.approx(1.0, rel=0.02)
    assert t.linear.y == pytest.approx(0.0, abs=0.11)
    assert t.angular.z == pytest.approx(0.4)
    assert odom.twist.covariance[0] == 0.02
    assert odom.twist.covariance[35] == 0.02
    assert odom.twist.covariance[14] == UNKNOWN_VARIANCE


def test_twist_across_the_pi_wrap():
    conv = PoseToOdometry()
    conv.convert(make_pose(x=0.0, y=0.0, yaw=math.pi - 0.05, t=1.0))
    odom = conv.convert(make_pose(x=0.0, y=0.0, yaw=-math.pi + 0.05, t=1.1))
    assert odom.twist.twist.angular.z == pytest.approx(1.0)


def test_twist_disabled_gives_unknown_zero():
    conv = PoseToOdometry(estimate_twist=False)
    conv.convert(make_pose(x=0.0, t=1.0))
    odom = conv.convert(make_pose(x=1.0, t=2.0))
    assert odom.twist.twist.linear.x == 0.0
    assert odom.twist.covariance[0] == UNKNOWN_VARIANCE


@pytest.mark.parametrize('bad', [0.0, -1.0, float('nan')])
def test_bad_twist_variance_is_rejected(bad):
    with pytest.raises(ValueError, match='twist_variance'):
        PoseToOdometry(twist_variance=bad)


def assert_zero_unknown_twist(odom):
    t = odom.twist.twist
    assert (t.linear.x, t.linear.y, t.angular.z) == (0.0, 0.0, 0.0)
    assert list(odom.twist.covariance) == list(UNKNOWN_TWIST_COVARIANCE)


def test_unknown_twist_covariance_is_diagonal_unknown():
    assert len(UNKNOWN_TWIST_COVARIANCE) == 36
    assert [UNKNOWN_TWIST_COVARIANCE[7 * i] for i in range(6)] == \
        [UNKNOWN_VARIANCE] * 6
    assert sum(UNKNOWN_TWIST_COVARIANCE) == 6 * UNKNOWN_VARIANCE


def test_poses_across_the_position_range_give_an_unknown_twist_not_inf():
    conv = PoseToOdometry()
    conv.convert(make_pose(x=-MAX_POSITION, y=0.0, yaw=0.0, t=1.0))
    odom = conv.convert(make_pose(x=MAX_POSITION, y=-MAX_POSITION, yaw=0.0,
                                  t=2.0))
    assert_zero_unknown_twist(odom)
    # The next ordinary step estimates a twist again.
    odom = conv.convert(make_pose(x=MAX_POSITION, y=-MAX_POSITION, yaw=0.1,
                                  t=3.0))
    assert odom.twist.twist.angular.z == pytest.approx(0.1)
    assert odom.twist.covariance[0] == 0.01


@pytest.mark.parametrize('dt', [1e-9, 5e-4, MIN_TWIST_DT / 2])
def test_poses_too_close_in_time_give_an_unknown_twist(dt):
    conv = PoseToOdometry()
    conv.convert(make_pose(x=0.0, t=1.0))
    odom = conv.convert(make_pose(x=1000.0, t=1.0 + dt))
    assert_zero_unknown_twist(odom)


def test_poses_just_far_enough_apart_give_a_twist():
    conv = PoseToOdometry()
    conv.convert(make_pose(x=0.0, yaw=0.0, t=1.0))
    odom = conv.convert(make_pose(x=0.01, yaw=0.0, t=1.0 + 2 * MIN_TWIST_DT))
    assert odom.twist.twist.linear.x == pytest.approx(5.0, rel=1e-3)


def test_twist_covariance_is_fresh_per_message():
    conv = PoseToOdometry()
    first = conv.convert(make_pose(t=1.0))
    first.twist.covariance[0] = 42.0  # a subscriber edits its message
    second = conv.convert(make_pose(t=1.0 + MIN_TWIST_DT / 2))
    assert second.twist.covariance[0] == UNKNOWN_VARIANCE


@pytest.mark.parametrize('dx,dyaw,dt', [(2 * MAX_TWIST, 0.0, 1.0),
                                        (-MAX_POSITION, 0.0, 1.0),
                                        (0.0, 3.0, 2e-3)])
def test_a_jump_gives_an_unknown_twist(dx, dyaw, dt):
    conv = PoseToOdometry()
    conv.convert(make_pose(x=0.0, y=0.0, yaw=0.0, t=1.0))
    odom = conv.convert(make_pose(x=dx, y=0.0, yaw=dyaw, t=1.0 + dt))
    assert_zero_unknown_twist(odom)


def test_a_fast_but_possible_twist_is_kept():
    conv = PoseToOdometry()
    conv.convert(make_pose(x=0.0, y=0.0, yaw=0.0, t=1.0))
    odom = conv.convert(make_pose(x=0.9 * MAX_TWIST * 0.01, y=0.0, yaw=0.0, t=1.01))
    assert odom.twist.twist.linear.x == pytest.approx(0.9 * MAX_TWIST)


# --- bad input and ROS time moving backwards ---------------------------------

def covariance_with(index, value):
    cov = [0.0] * 36
    for i in range(0, 36, 7):
        cov[i] = 0.01
    cov[index] = value
    return cov


@pytest.mark.parametrize('change,kind', [
    (dict(t=0.0), ZERO_STAMP), (dict(t=9.5), OUT_OF_ORDER),
    (dict(t=10.0), DUPLICATE), (dict(x=1e300), ABSURD),
    (dict(y=-MAX_POSITION * 2), ABSURD),
    (dict(cov=covariance_with(7, -0.01)), NEGATIVE_VARIANCE),
    (dict(cov=covariance_with(35, float('inf'))), NOT_FINITE),
    (dict(cov=covariance_with(1, 1e300)), ABSURD)])
def test_each_kind_of_bad_pose_is_dropped(change, kind):
    conv = PoseToOdometry()
    conv.convert(make_pose(x=0.0, y=0.0, yaw=0.0, t=10.0))
    bad = dict(dict(t=11.0), **change)
    with pytest.raises(RejectedInput) as caught:
        conv.convert(make_pose(**bad))
    assert caught.value.kind == kind
    text = conv.inputs.warning(caught.value, 11.0, 'pose on /odom_combined')
    assert text.startswith('dropped pose on /odom_combined: ' + kind)
    # The next good pose is taken, its twist measured from the last good one.
    odom = conv.convert(make_pose(x=1.0, y=0.0, yaw=0.0, t=11.0))
    assert odom.twist.twist.linear.x == pytest.approx(1.0)


def test_output_stamps_only_move_forward_through_bad_input():
    # The stream: zero stamps, out-of-order poses, a negative
    # variance and 1e300 positions among good poses.
    stream = [make_pose(t=1.0), make_pose(t=0.0), make_pose(t=2.0),
              make_pose(t=1.5), make_pose(t=2.5, cov=covariance_with(0, -1.0)),
              make_pose(t=3.0, x=1e300), make_pose(t=3.5), make_pose(t=3.5),
              make_pose(t=4.0)]
    conv, stamps, dropped = PoseToOdometry(), [], []
    for msg in stream:
        try:
            stamps.append(conv.convert(msg).header.stamp.to_sec())
        except RejectedInput as err:
            dropped.append(err.kind)
    assert stamps == [1.0, 2.0, 3.5, 4.0]
    assert dropped == [ZERO_STAMP, OUT_OF_ORDER, NEGATIVE_VARIANCE, ABSURD,
                       DUPLICATE]


def test_time_moving_back_takes_the_new_clocks_poses():
    conv = PoseToOdometry()
    assert conv.check_clock(100.0) == 0.0
    conv.convert(make_pose(x=0.0, t=100.0))
    assert conv.check_clock(100.1) == 0.0
    conv.convert(make_pose(x=0.1, t=100.1))
    assert conv.check_clock(90.1) == pytest.approx(10.0)
    odom = conv.convert(make_pose(x=5.0, yaw=0.0, t=90.1))
    assert odom.header.stamp.to_sec() == pytest.approx(90.1)
    assert_zero_unknown_twist(odom)  # no twist across the jump
    odom = conv.convert(make_pose(x=5.1, yaw=0.0, t=90.2))
    assert odom.twist.twist.linear.x == pytest.approx(1.0)


def test_a_silent_input_is_named_with_the_topics_to_remap_to():
    text = silent_input_text('/odom_combined', 5.0, [],
                             ['/odom_combined', '/robot_pose_ekf/odom_combined'])
    assert text.startswith('nothing on /odom_combined after 5 s; nothing publishes it.')
    assert 'odom_ekf.launch input:=/robot_pose_ekf/odom_combined' in text
    assert 'pose_ekf.py' in silent_input_text('/odom_combined', 5.0, [], [])
    assert '/robot_pose_ekf publishes it' in silent_input_text(
        '/odom_combined', 5.0, ['/robot_pose_ekf'], ['/odom_combined'])
    assert 'unknown' in silent_input_text('/odom_combined', 5.0, None, None)


def test_the_input_publishers_and_the_topics_to_remap_to_come_from_the_graph():
    graph = ({'/odom_combined': ['/ekf'], '/robot_pose_ekf/odom_combined':
              ['/robot_pose_ekf'], '/odom': ['/sim'], '/old': []},
             {}, {'/odom_combined': POSE_TYPE,
                  '/robot_pose_ekf/odom_combined': POSE_TYPE,
                  '/odom': 'nav_msgs/Odometry', '/old': POSE_TYPE})
    publishers, candidates = input_publishers('/odom_combined', graph)
    assert publishers == ['/ekf']
    assert sorted(candidates) == ['/odom_combined',
                                  '/robot_pose_ekf/odom_combined']
    assert input_publishers('/nothing', graph)[0] == []
    assert input_publishers('/odom_combined', None) == (None, None)


BOOK, OWN = '/odom_combined', '/robot_pose_ekf/odom_combined'


def test_the_default_inputs_are_the_books_and_the_filters_own():
    assert DEFAULT_INPUTS == (BOOK_INPUT, FILTER_INPUT)
    assert (BOOK_INPUT, FILTER_INPUT) == ('odom_combined',
                                          'robot_pose_ekf/odom_combined')


@pytest.mark.parametrize('first, other', [(BOOK, OWN), (OWN, BOOK)])
def test_the_first_input_to_deliver_is_followed_and_the_other_named_once(
        first, other):
    choice = InputChoice([BOOK, OWN])
    taken = choice.offer(first, 0.0)
    assert taken.take and not taken.switched and taken.level == 'info'
    assert taken.text == 'following %s (the first of %s and %s to publish)' % (
        first, BOOK, OWN)
    assert choice.offer(first, 0.1).take
    assert choice.offer(first, 0.1).text is None
    dropped = choice.offer(other, 0.2)
    assert not dropped.take and dropped.level == 'warn'
    assert dropped.text.startswith('both %s and %s carry a fused pose: '
                                   'following %s' % (first, other, first))
    assert 'odom_ekf.launch input:=%s' % other in dropped.text
    # One warning: the next poses of the other input are dropped silently.
    for t in (0.3, 0.4, 4.9):
        assert choice.offer(first, t).take
        again = choice.offer(other, t)
        assert not again.take and again.text is None
    assert choice.followed == first


def test_the_other_input_is_followed_once_the_first_is_silent():
    choice = InputChoice([BOOK, OWN])
    choice.offer(OWN, 0.0)
    assert not choice.offer(BOOK, SWITCH_AFTER - 0.01).take
    switched = choice.offer(BOOK, SWITCH_AFTER)
    assert switched.take and switched.switched and switched.level == 'warn'
    assert switched.text == ('nothing on %s for 5 s while %s publishes: '
                             'following %s now' % (OWN, BOOK, BOOK))
    assert choice.followed == BOOK
    back = choice.offer(OWN, SWITCH_AFTER + 0.1)  # the old one is back
    assert not back.take and 'following %s' % BOOK in back.text
    assert choice.offer(BOOK, SWITCH_AFTER + 0.2).take


def test_a_remapped_input_alone_is_followed():
    choice = InputChoice(['/my_filter/pose'])
    assert choice.offer('/my_filter/pose', 0.0).text == 'following /my_filter/pose'
    with pytest.raises(ValueError):
        choice.offer(BOOK, 0.1)
    with pytest.raises(ValueError):
        InputChoice([])


def test_after_a_switch_the_new_filters_poses_are_taken_from_scratch():
    odom = PoseToOdometry()
    odom.convert(make_pose(x=0.0, t=10.0))
    odom.convert(make_pose(x=0.1, t=10.1))
    # The other filter's clock or stamps lag: without new_input its pose
    # would be dropped as out of order.
    with pytest.raises(RejectedInput):
        odom.convert(make_pose(x=5.0, t=10.05))
    odom.new_input()
    out = odom.convert(make_pose(x=5.0, t=10.05))
    assert out.pose.pose.position.x == 5.0
    # No twist across the switch.
    assert list(out.twist.covariance) == list(UNKNOWN_TWIST_COVARIANCE)


def test_both_silent_inputs_are_named_with_their_publishers():
    text = silent_input_text([BOOK, OWN], 5.0, [], [BOOK, OWN, '/gps_pose'])
    assert text.startswith('nothing on %s or %s after 5 s; nothing publishes '
                           'it.' % (BOOK, OWN))
    assert 'input:=/gps_pose' in text
    graph = ({BOOK: ['/ekf'], OWN: ['/robot_pose_ekf']}, {},
             {BOOK: POSE_TYPE, OWN: POSE_TYPE})
    assert input_publishers([BOOK, OWN], graph)[0] == ['/ekf', '/robot_pose_ekf']
