"""rbx1_nav.motion.runner.invalid_poses: what tf2 drops (NaN, a rotation that is not a unit
quaternion) is judged as tf2 judges it, and the course's texts name the node and the fault."""
import math

import pytest

from rbx1_nav.motion.runner.invalid_poses import (UNIT_TOLERANCE, InvalidPoses, invalid_odom_text,
                                           invalid_update_text, no_transform_text, pose_problem)

NAN, INF = float('nan'), float('inf')
ORIGIN, IDENTITY = (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)


@pytest.mark.parametrize('position,rotation', [
    (ORIGIN, IDENTITY),
    ((1e6, -3.0, 0.0), (0.0, 0.0, math.sin(1.0), math.cos(1.0))),
    # tf2's BufferCore keeps |x²+y²+z²+w² - 1| up to 0.01 (measured: w 1.0049 kept, 1.0051
    # dropped; 0.995 kept, 0.9949 dropped).
    (ORIGIN, (0.0, 0.0, 0.0, 1.0049)),
    (ORIGIN, (0.0, 0.0, 0.0, 0.995)),
])
def test_what_tf2_keeps_is_valid(position, rotation):
    assert pose_problem(position, rotation) is None


@pytest.mark.parametrize('position,rotation,text', [
    ((NAN, NAN, 0.0), (0.0, 0.0, NAN, NAN),
     'NaN in the position (nan, nan, 0) and the rotation (0, 0, nan, nan)'),
    ((NAN, 0.0, 0.0), IDENTITY, 'NaN in the position (nan, 0, 0)'),
    (ORIGIN, (0.0, 0.0, 0.0, NAN), 'NaN in the rotation (0, 0, 0, nan)'),
    ((INF, 0.0, 0.0), IDENTITY, 'infinity in the position (inf, 0, 0)'),
    (ORIGIN, (0.0, 0.0, 0.0, 2.0),
     'a rotation (0, 0, 0, 2) that is not a unit quaternion (length 2)'),
    (ORIGIN, (0.0, 0.0, 0.0, 0.0),
     'a rotation (0, 0, 0, 0) that is not a unit quaternion (length 0)'),
    (ORIGIN, (0.0, 0.0, 0.0, 1.0051),
     'a rotation (0, 0, 0, 1.0051) that is not a unit quaternion (length 1.01)'),
])
def test_what_tf2_drops_is_named(position, rotation, text):
    assert pose_problem(position, rotation) == text


def test_the_tolerance_is_on_the_squared_length():
    w = math.sqrt(1.0 + UNIT_TOLERANCE)
    assert pose_problem(ORIGIN, (0.0, 0.0, 0.0, w * 0.9999)) is None
    assert pose_problem(ORIGIN, (0.0, 0.0, 0.0, w * 1.0001)) is not None


def test_a_velocity_is_judged_when_given():
    assert pose_problem(ORIGIN, IDENTITY, (0.2, 0.0)) is None
    assert pose_problem(ORIGIN, IDENTITY, (0.0, NAN)) == 'NaN in the velocity (0, nan)'
    assert pose_problem((NAN, NAN, 0.0), IDENTITY, (0.0, NAN)) == (
        'NaN in the position (nan, nan, 0) and the velocity (0, nan)')


def test_invalid_poses_counts_per_node_and_keeps_the_latest():
    poses = InvalidPoses()
    assert not poses
    assert poses.heard('/b', 'NaN in the position (nan, 0, 0)') is True
    assert poses.heard('/b', 'NaN in the rotation (0, 0, 0, nan)') is False
    assert poses and poses.count() == 2 and poses.names() == '/b'
    assert poses.text() == 'NaN in the rotation (0, 0, 0, nan)'
    assert poses.heard('/a', 'infinity in the position (inf, 0, 0)') is True
    assert poses.names() == '/a, /b'
    assert poses.text() == ('1 from /a: infinity in the position (inf, 0, 0); '
                            '2 from /b: NaN in the rotation (0, 0, 0, nan)')


def test_no_transform_heard_is_still_nothing_publishing():
    problem, fix = no_transform_text('odom', ('base_footprint', 'base_link'), 5.0, {})
    assert problem == ('no transform from odom to base_footprint or base_link after 5.0 s: '
                       'nothing is publishing the robot\'s odometry on tf')
    assert 'fake_turtlebot.launch' in fix and 'driver' in fix


def test_invalid_transforms_heard_name_the_node_and_the_fault():
    poses = InvalidPoses()
    nan = pose_problem((NAN, NAN, 0.0), (0.0, 0.0, NAN, NAN))
    for _ in range(50):
        poses.heard('/turtlebot3_fake_node', nan)
    problem, fix = no_transform_text('odom', ('base_footprint', 'base_link'), 2.0,
                                     {'base_footprint': poses, 'base_link': InvalidPoses()})
    assert problem == (
        'tf odom -> base_footprint comes from /turtlebot3_fake_node, but all 50 transforms of '
        'it in 2.0 s were invalid (NaN in the position (nan, nan, 0) and the rotation '
        '(0, 0, nan, nan)), and tf drops invalid transforms: the robot\'s driver is running but '
        'publishes a broken pose')
    assert 'nothing is publishing' not in problem
    assert fix.startswith('Fix /turtlebot3_fake_node (ROBOTIS\' turtlebot3_fake_node publishes '
                          'NaN when its tb3_model parameter is not burger, waffle or waffle_pi')
    assert fix.endswith('The robot was not moved.')
    assert '\n' not in problem + fix


def test_an_invalid_update_mid_course_and_invalid_odometry():
    text = invalid_update_text('odom', 'base_footprint', '/d', 'NaN in the rotation (0, 0, 0, nan)')
    assert text.startswith('tf odom -> base_footprint from /d is invalid (NaN in the rotation '
                           '(0, 0, 0, nan)), and tf drops invalid transforms')
    assert 'Stopped the robot. Fix /d (' in text
    text = invalid_odom_text('/odom', '/d', 'NaN in the velocity (0, nan)')
    assert text.startswith('/odom from /d is invalid (NaN in the velocity (0, nan)): a fault in '
                           'the robot\'s driver, /d.')
