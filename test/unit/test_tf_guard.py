"""rbx1_nav.motion.runner.tf_guard: a transform from two nodes, or one that jumps
further than the robot can move at the course's speeds, is named once."""
import math

import pytest

from rbx1_nav.common.tf_publishers import foreign_parent, robot_conflict_text
from rbx1_nav.motion.course.course import Course, legs_course
from rbx1_nav.motion.runner.tf_guard import (EXTRA_ANGULAR, EXTRA_LINEAR, MARGIN,
                                      SLACK_ANGULAR, SLACK_LINEAR,
                                      TransformGuard, top_speeds)


def guard(linear=0.2, angular=1.0):
    return TransformGuard('odom', 'base_footprint', linear, angular)


def test_a_course_driven_at_its_speeds_passes():
    g = guard()
    for k in range(200):  # 4 s at 50 Hz: forward at 0.2 m/s, turning at 1 rad/s
        t = 0.02 * k
        assert g.heard('/fake_turtlebot', t, 0.2 * t, 0.0, 1.0 * t) is None
    assert g.problem is None


def test_a_second_publisher_is_named_with_the_fix():
    g = guard()
    assert g.heard('/fake_turtlebot', 1.0, 0.0, 0.0, 0.0) is None
    text = g.heard('/robot1/fake_turtlebot', 1.02, 0.0, 0.0, 0.0)
    assert text.startswith('tf odom -> base_footprint comes from two nodes, '
                           '/fake_turtlebot and /robot1/fake_turtlebot')
    assert 'Stopped the robot.' in text
    assert '_odom_frame:=robot1/odom' in text and '/tf:=tf' in text
    assert '\n' not in text
    # The first problem is kept.
    assert g.heard('/fake_turtlebot', 1.04, 9.0, 0.0, 0.0) == text


def test_the_issues_jump_is_refused():
    """6.77 m in 0.6 s, at the book's 0.2 m/s."""
    g = guard()
    g.heard('/fake_turtlebot', 10.0, 0.0, 0.0, 0.0)
    text = g.heard('/fake_turtlebot', 10.6, 6.77, 0.0, 0.0)
    assert text.startswith('tf odom -> base_footprint moved 6.770 m in 0.60 s '
                           '(limit 0.590 m)')
    assert "odometry reset" in text and '/tf:=tf' in text


@pytest.mark.parametrize('dt', [0.0, 0.02, 0.6])
def test_the_limit_is_margin_times_top_speed_plus_extra_per_second_plus_slack(dt):
    linear, angular = 0.3, 1.5
    limit = (MARGIN * linear + EXTRA_LINEAR) * dt + SLACK_LINEAR
    within, beyond = guard(linear, angular), guard(linear, angular)
    for g in (within, beyond):
        g.heard('/robot', 5.0, 1.0, 1.0, 0.0)
    assert within.heard('/robot', 5.0 + dt, 1.0 + 0.999 * limit, 1.0, 0.0) is None
    assert beyond.heard('/robot', 5.0 + dt, 1.0, 1.0 + 1.001 * limit, 0.0)
    turn = (MARGIN * angular + EXTRA_ANGULAR) * dt + SLACK_ANGULAR
    within, beyond = guard(linear, angular), guard(linear, angular)
    for g in (within, beyond):
        g.heard('/robot', 5.0, 0.0, 0.0, math.pi - 0.01)  # across +-pi
    assert within.heard('/robot', 5.0 + dt, 0.0, 0.0,
                        math.pi - 0.01 + 0.999 * turn) is None
    assert 'deg in' in beyond.heard('/robot', 5.0 + dt, 0.0, 0.0,
                                    math.pi - 0.01 - 1.001 * turn)


def test_time_moving_back_starts_the_comparison_again():
    g = guard()
    g.heard('/robot', 10.0, 5.0, 0.0, 0.0)
    assert g.heard('/robot', 2.0, 0.0, 0.0, 0.0) is None  # a restarted clock
    assert g.heard('/robot', 2.02, 0.004, 0.0, 0.0) is None


def test_top_speeds_of_a_course():
    closed = Course(legs_course(1.0, math.pi, 2, 0.15, 0.8,
                                tolerance=math.radians(1.0)))
    assert top_speeds(closed) == (0.15, 0.8)
    timed = Course(legs_course(1.0, math.pi, 2, 0.15, 0.8, period=0.05))
    assert top_speeds(timed) == (0.15, 0.8)


def test_the_fake_robots_conflict_line_names_the_node_and_fix():
    text = robot_conflict_text('/robot1/fake_turtlebot', 'odom', 'base_footprint', '/tf')
    assert text.startswith('node /robot1/fake_turtlebot also publishes the '
                           'transform odom -> base_footprint on /tf')
    assert '_odom_frame:=robot1/odom' in text and '/tf:=tf' in text


def test_only_another_nodes_transform_of_our_child_frame_is_foreign():
    from types import SimpleNamespace as T
    tfs = [T(child_frame_id='wheel', header=T(frame_id='base_footprint')),
           T(child_frame_id='/base_footprint', header=T(frame_id='/odom'))]
    assert foreign_parent('/other', '/me', tfs, 'base_footprint') == 'odom'
    assert foreign_parent('/me', '/me', tfs, 'base_footprint') is None
    assert foreign_parent('/other', '/me', tfs[:1], 'base_footprint') is None


def test_an_invalid_update_is_named_and_kept():
    g = guard()
    assert g.heard('/fake_turtlebot', 1.0, 0.0, 0.0, 0.0) is None
    text = g.invalid('/fake_turtlebot', 'NaN in the position (nan, nan, 0)')
    assert text.startswith('tf odom -> base_footprint from /fake_turtlebot is invalid (NaN in '
                           'the position (nan, nan, 0))')
    assert 'Stopped the robot.' in text
    assert g.problem == text
    # The first problem is kept.
    assert g.heard('/robot1/fake_turtlebot', 1.02, 0.0, 0.0, 0.0) == text
    assert g.invalid('/x', 'NaN in the rotation (0, 0, 0, nan)') == text
