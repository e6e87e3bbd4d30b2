"""pose_ekf's GPS modes on robot_pose_ekf's own Husky bag
(test/data/gps_data.bag), replayed without ROS running by
bench/accuracy/pose_ekf_husky.py: robot_pose_ekf's test passes offline, the answer
does not depend on when the node's timer fires or when it started, and
gps_frame_rotation follows the fixes more closely than robot_pose_ekf's
mode. Needs rosbag (skipped without it, e.g. under Python 3.8 alone)."""
import math
import os
import sys

import numpy as np
import pytest

rosbag = pytest.importorskip('rosbag')
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..',
                                'bench', 'accuracy'))
import pose_ekf_husky as husky  # noqa: E402
from rbx1_nav.estimation.fusion import GyroOdomFusion  # noqa: E402
from rbx1_nav.transform_utils import normalize_angle  # noqa: E402

ROTATION = husky.MODES['gps_frame_rotation']
EPS_TRANS = 0.1  # m, robot_pose_ekf's test, per axis
EPS_QUATERNION = 0.005  # robot_pose_ekf's test, on quaternion z and w
AGREE_M, AGREE_DEG = 0.01, 0.2  # one run started late against another


@pytest.fixture(scope='module')
def messages():
    return husky.read_bag()


def run(messages, options=None, **replay_options):
    fusion = GyroOdomFusion(gps_used=True, **(options or {}))
    return husky.replay(fusion, messages, **replay_options)


def test_robot_pose_ekf_mode_passes_robot_pose_ekfs_gps_test(messages):
    estimates = run(messages)
    _, (x, y, yaw), _ = husky.last_before(estimates)
    assert x == pytest.approx(husky.EXPECTED[0], abs=EPS_TRANS)
    assert y == pytest.approx(husky.EXPECTED[1], abs=EPS_TRANS)
    expected = math.radians(husky.EXPECTED[2])
    assert math.sin(yaw / 2) == pytest.approx(math.sin(expected / 2),
                                              abs=EPS_QUATERNION)
    assert math.cos(yaw / 2) == pytest.approx(math.cos(expected / 2),
                                              abs=EPS_QUATERNION)
    assert len([e for e in estimates if e[0] < husky.END]) > 200


@pytest.mark.parametrize('options', [None, ROTATION])
def test_the_answer_does_not_depend_on_when_the_filter_steps(messages,
                                                             options):
    """30 Hz ticks against ticks 5 to 100 ms apart at random (a loaded
    machine, a bag played fast): the same estimates at the same stamps
    (to a nanometre: floating-point rounding)."""
    steady = run(messages, options)
    rng = np.random.default_rng(1)
    start = messages[0][0]
    ticks = start + np.cumsum(rng.uniform(0.005, 0.1, 2000))
    jittered = run(messages, options, ticks=ticks)
    jittered = {e[0]: e[1] for e in jittered}
    for stamp, pose, _ in steady:
        if stamp in jittered:
            assert jittered[stamp] == pytest.approx(pose, abs=1e-9)
    assert husky.last_before(steady)[0] in jittered


def test_gps_frame_rotation_started_late_gives_the_same_answer(messages):
    ends = [husky.last_before(run(messages, ROTATION, skip=skip))[1]
            for skip in (0.0, 1.5, 3.0)]
    for x, y, yaw in ends[1:]:
        assert math.hypot(x - ends[0][0], y - ends[0][1]) < AGREE_M
        assert abs(math.degrees(normalize_angle(yaw - ends[0][2]))) < AGREE_DEG


def fix_distance(messages, estimates):
    """RMS distance (m) of the estimates from the fixes at the fixes'
    stamps, after the first 5 s."""
    poses = {e[0]: e[1][:2] for e in estimates}
    start = messages[0][2] + 5.0
    d = [math.hypot(*np.subtract(m[3], poses[m[2]])) for m in messages
         if m[1] == 'gps' and m[2] in poses and m[2] > start]
    assert len(d) > 60
    return math.sqrt(np.mean(np.square(d)))


def test_gps_frame_rotation_follows_the_fixes_closer(messages):
    """robot_pose_ekf takes the IMU's heading as true in the GPS frame;
    estimating the rotation between them (found about 9 deg) keeps the
    estimate at least twice as close to the fixes."""
    fusion = GyroOdomFusion(gps_used=True, **ROTATION)
    rotated = husky.replay(fusion, messages)
    assert fix_distance(messages, rotated) < 0.5 * fix_distance(
        messages, run(messages))
    rotation, variance = fusion.ekf.rotation
    assert 2.0 * math.sqrt(variance) < abs(rotation)  # told apart from 0


@pytest.mark.parametrize('options', [None, ROTATION])
def test_a_node_starved_of_the_cpu_gives_the_same_answer(messages, options):
    """Every message of 2 s (two sensor timeouts) read at once at its end,
    as a node starved of the CPU reads its queues, its timer firing first:
    no sensor counts as lost, and the estimates are the same."""
    t0 = messages[0][0] + 10.0
    starved = [(t0 + 2.0,) + m[1:] if t0 <= m[0] < t0 + 2.0 else m
               for m in messages]
    fusion = GyroOdomFusion(gps_used=True, **(options or {}))
    estimates = husky.replay(fusion, starved)
    assert 'dropped' not in fusion.state()
    steady = {e[0]: e[1] for e in run(messages, options)}
    assert [e[0] for e in estimates] == sorted(steady)
    for stamp, pose, _ in estimates:
        assert pose == pytest.approx(steady[stamp], abs=1e-9)
