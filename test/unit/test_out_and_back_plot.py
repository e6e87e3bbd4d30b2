"""Unit tests for rbx1_nav.motion.plot.course_plot (the plotting half of plot_course.py)."""
import math

import pytest

from rbx1_nav.motion.plot.course_plot import (Track, describe_error, describe_final_offset,
                                         end_error, final_offset, plot_course)


def square_track(name, end_offset=(0.0, 0.0, 0.0)):
    track = Track(name)
    for x, y, yaw in [(0, 0, 0), (1, 0, 0), (1, 0, math.pi), (0, 0, math.pi)]:
        track.add(x, y, yaw)
    dx, dy, dyaw = end_offset
    track.add(dx, dy, dyaw)
    return track


def test_end_error_is_end_pose_against_start_pose():
    track = square_track('odom', (0.003, -0.004, math.radians(1.0)))
    dist, heading = end_error(track)
    assert dist == pytest.approx(0.005)
    assert heading == pytest.approx(math.radians(1.0))
    assert describe_error(track) == 'odom: 5.0 mm, +1.00 deg'


def test_end_error_wraps_heading():
    track = Track('t', [(0, 0, math.pi - 0.01), (0, 0, -math.pi + 0.01)])
    assert end_error(track)[1] == pytest.approx(0.02)


def test_length_sums_the_path():
    assert square_track('odom').length == pytest.approx(2.0)


def test_empty_track_has_no_error():
    with pytest.raises(ValueError, match='no poses'):
        end_error(Track('odom'))


def test_plot_writes_a_png_with_errors_in_the_title(tmp_path):
    pytest.importorskip('matplotlib')
    out = tmp_path / 'course.png'
    title = plot_course([square_track('odom'),
                         square_track('ground truth', (0.01, 0, 0))],
                        str(out), title='run 1')
    assert out.read_bytes()[:8] == b'\x89PNG\r\n\x1a\n'
    assert title.startswith('run 1\n')
    from PIL import Image  # make deps installs it (python3-pil)
    with Image.open(str(out)) as image:
        assert image.text['Title'] == title
    assert 'odom: 0.0 mm' in title and 'ground truth: 10.0 mm' in title


def test_plot_skips_empty_tracks_like_a_bag_without_ground_truth(tmp_path):
    pytest.importorskip('matplotlib')
    title = plot_course([square_track('odom'), Track('ground truth')],
                        str(tmp_path / 'odom_only.png'))
    assert 'ground truth' not in title


def test_plot_refuses_when_nothing_to_draw(tmp_path):
    with pytest.raises(ValueError, match='nothing to plot'):
        plot_course([Track('odom')], str(tmp_path / 'x.png'))


def test_final_offset_against_a_reference_track():
    truth = square_track('ground truth')
    fused = square_track('fused', (0.03, 0.04, 0.0))
    assert final_offset(fused, truth) == pytest.approx(0.05)
    assert describe_final_offset(fused, truth) == (
        'fused: 50.0 mm from ground truth')
    with pytest.raises(ValueError):
        final_offset(Track('fused'), truth)


def test_plot_with_a_fused_track_gives_distances_from_the_truth(tmp_path):
    pytest.importorskip('matplotlib')
    truth = square_track('ground truth')
    title = plot_course([square_track('odom', (0.3, 0.0, 0.0)), truth,
                         square_track('fused', (0.0, 0.02, 0.0))],
                        str(tmp_path / 'fused.png'), reference=truth)
    assert title.splitlines()[2] == ('at the end: odom: 300.0 mm from ground '
                                     'truth; fused: 20.0 mm from ground truth')
