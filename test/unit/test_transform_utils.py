"""Unit tests for rbx1_nav.transform_utils (no ROS master needed)."""
import math
from types import SimpleNamespace

import pytest
from hypothesis import given, strategies as st

from rbx1_nav.transform_utils import (normalize_angle, quat_to_angle,
                                      strip_leading_slash, yaw_to_quaternion)

finite = st.floats(allow_nan=False, allow_infinity=False)
component = st.floats(-1e3, 1e3, allow_nan=False)


def hamilton(a, b):
    """Quaternion product a*b of (x, y, z, w) tuples."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def oracle_yaw(q):
    """Yaw as the heading of the body x axis rotated by q (q v q*)."""
    n = math.sqrt(sum(c * c for c in q))
    q = tuple(c / n for c in q)
    conj = (-q[0], -q[1], -q[2], q[3])
    vx, vy, _, _ = hamilton(hamilton(q, (1.0, 0.0, 0.0, 0.0)), conj)
    return math.atan2(vy, vx)


def axis_quat(axis, angle):
    s = math.sin(angle / 2.0)
    v = [0.0, 0.0, 0.0]
    v[axis] = s
    return (v[0], v[1], v[2], math.cos(angle / 2.0))


def angles_close(a, b, tol):
    return abs(math.remainder(a - b, 2.0 * math.pi)) <= tol


# --- quat_to_angle -----------------------------------------------------------

def test_identity_is_zero():
    assert quat_to_angle((0.0, 0.0, 0.0, 1.0)) == 0.0


def test_half_turn_is_plus_pi_never_minus_pi():
    assert quat_to_angle((0.0, 0.0, 1.0, 0.0)) == math.pi
    assert quat_to_angle((0.0, 0.0, -1.0, 0.0)) == math.pi
    assert quat_to_angle((0.0, 0.0, 1.0, -0.0)) == math.pi


def test_accepts_message_like_objects_and_sequences():
    q = axis_quat(2, 0.5)
    msg = SimpleNamespace(x=q[0], y=q[1], z=q[2], w=q[3])
    assert quat_to_angle(msg) == pytest.approx(0.5, abs=1e-12)
    assert quat_to_angle(list(q)) == pytest.approx(0.5, abs=1e-12)


def test_accepts_geometry_msgs_quaternion():
    geometry_msgs = pytest.importorskip('geometry_msgs.msg')
    q = axis_quat(2, -1.25)
    msg = geometry_msgs.Quaternion(*q)
    assert quat_to_angle(msg) == pytest.approx(-1.25, abs=1e-12)


def test_non_unit_quaternion_is_normalised():
    q = axis_quat(2, 2.0)
    assert quat_to_angle([7.5 * c for c in q]) == pytest.approx(2.0, abs=1e-12)


@pytest.mark.parametrize('bad', [(0, 0, 0, 0), (0, 0, float('nan'), 1),
                                 (float('inf'), 0, 0, 1)])
def test_degenerate_quaternion_raises(bad):
    with pytest.raises(ValueError, match='zero length|non-finite'):
        quat_to_angle(bad)


@pytest.mark.parametrize('bad', [(0, 0, 1), 'abcd1', 42])
def test_malformed_input_raises_value_error(bad):
    with pytest.raises(ValueError):
        quat_to_angle(bad)


@given(st.tuples(component, component, component, component)
       .filter(lambda q: sum(c * c for c in q) > 1e-6))
def test_yaw_matches_rotated_x_axis(q):
    yaw = quat_to_angle(q)
    assert -math.pi < yaw <= math.pi
    # The heading of the rotated x axis is undefined when it points along z.
    n = math.sqrt(sum(c * c for c in q))
    x, y, z, w = (c / n for c in q)
    if math.hypot(1 - 2 * (y * y + z * z), 2 * (x * y + w * z)) > 1e-6:
        assert angles_close(yaw, oracle_yaw(q), 1e-6)


@given(st.floats(-math.pi, math.pi), st.floats(-1.5, 1.5),
       st.floats(-math.pi, math.pi))
def test_yaw_of_zyx_euler_rotation(yaw, pitch, roll):
    q = hamilton(hamilton(axis_quat(2, yaw), axis_quat(1, pitch)),
                 axis_quat(0, roll))
    assert angles_close(quat_to_angle(q), yaw, 1e-9)


# --- normalize_angle ---------------------------------------------------------

@pytest.mark.parametrize('angle, expected', [
    (0.0, 0.0), (math.pi / 2, math.pi / 2), (2 * math.pi, 0.0),
    (3 * math.pi / 2, -math.pi / 2), (-3 * math.pi / 2, math.pi / 2),
    (7 * math.pi + 0.25, -math.pi + 0.25),
])
def test_normalize_known_values(angle, expected):
    assert normalize_angle(angle) == pytest.approx(expected, abs=1e-12)


@given(finite)
def test_normalized_angle_is_in_range_and_equivalent(angle):
    r = normalize_angle(angle)
    assert -math.pi <= r <= math.pi
    if abs(angle) < 1e6:  # beyond that, cos/sin of the input lose precision
        assert math.cos(r) == pytest.approx(math.cos(angle), abs=1e-9)
        assert math.sin(r) == pytest.approx(math.sin(angle), abs=1e-9)


@given(st.floats(-math.pi + 1e-9, math.pi - 1e-9))
def test_angles_in_range_are_unchanged(angle):
    assert normalize_angle(angle) == pytest.approx(angle, abs=1e-15)


@given(st.floats(-1e3, 1e3), st.integers(-10 ** 6, 10 ** 6))
def test_adding_full_turns_changes_nothing(angle, turns):
    a = normalize_angle(angle)
    b = normalize_angle(angle + turns * 2 * math.pi)
    assert angles_close(a, b, 1e-6)


def test_very_large_angles_are_handled():
    for angle in (1e300, -1e300, 1.7976931348623157e308):
        assert -math.pi <= normalize_angle(angle) <= math.pi


@pytest.mark.parametrize('bad', [float('nan'), float('inf'), -float('inf')])
def test_normalize_rejects_non_finite(bad):
    with pytest.raises(ValueError, match='non-finite'):
        normalize_angle(bad)


# --- yaw_to_quaternion, strip_leading_slash ----------------------------------

@given(st.floats(-math.pi + 1e-9, math.pi))
def test_yaw_to_quaternion_round_trips(yaw):
    q = yaw_to_quaternion(yaw)
    assert sum(c * c for c in q) == pytest.approx(1.0, abs=1e-12)
    assert angles_close(quat_to_angle(q), yaw, 1e-12)
    assert angles_close(oracle_yaw(q), yaw, 1e-9)


@pytest.mark.parametrize('given_id, expected', [
    ('/odom', 'odom'), ('//base_link', 'base_link'), ('robot1/odom', 'robot1/odom'),
    ('base_footprint', 'base_footprint'), ('', '')])
def test_strip_leading_slash(given_id, expected):
    assert strip_leading_slash(given_id) == expected
