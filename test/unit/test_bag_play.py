"""rbx1_nav.sim.bag_play: what a lockstep bag player publishes at each grant."""
from rbx1_nav.sim.bag_play import Schedule

S = 1000000000  # ns


def bag():
    return [(100 * S, '/odom', 'o1'), (100 * S + 5, '/imu', 'i1'),
            (101 * S, '/odom', 'o2'), (103 * S, '/gps', 'g1')]


def test_each_grant_publishes_what_was_recorded_up_to_it_then_asks_for_the_next():
    schedule = Schedule(bag())
    assert schedule.next_time == 100 * S
    assert schedule.due(50 * S) == []  # before the bag: nothing
    assert schedule.due(100 * S + 5) == [('/odom', 'o1'), ('/imu', 'i1')]
    assert schedule.next_time == 101 * S
    assert schedule.due(102 * S) == [('/odom', 'o2')]
    assert schedule.due(103 * S) == [('/gps', 'g1')]
    assert schedule.next_time is None and schedule.played == 4


def test_a_start_skips_the_bags_first_seconds():
    schedule = Schedule(bag(), start=1.0)
    assert schedule.next_time == 101 * S
    assert schedule.due(200 * S) == [('/odom', 'o2'), ('/gps', 'g1')]


def test_an_empty_bag_or_a_start_past_its_end_has_nothing_to_play():
    assert Schedule([]).next_time is None
    assert Schedule(bag(), start=10.0).next_time is None
