"""Unit tests for rbx1_nav.common.throttle (no ROS master needed)."""
from rbx1_nav.common.throttle import Throttle


def test_throttle_repeats_a_warning_once_per_period_per_key():
    throttle = Throttle(period=5.0)
    assert throttle.ready(('robot1', 'clamped'), 10.0)
    assert not throttle.ready(('robot1', 'clamped'), 12.0)
    # Another robot or another warning is not held back by the first.
    assert throttle.ready(('robot2', 'clamped'), 12.0)
    assert throttle.ready(('robot1', 'non-finite'), 12.0)
    assert not throttle.ready(('robot1', 'clamped'), 15.0)
    assert throttle.ready(('robot1', 'clamped'), 15.01)


def test_throttle_allows_the_warning_again_when_time_moves_backwards():
    throttle = Throttle(period=5.0)
    assert throttle.ready('clamped', 100.0)
    assert throttle.ready('clamped', 3.0)  # a restarted simulation clock
    assert not throttle.ready('clamped', 4.0)
