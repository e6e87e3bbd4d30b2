"""The seam that keeps simulated time out of motion/: a course's clock and
link to the robot are rbx1_nav.motion.runner.clock_ros.RateClock and
rbx1_nav.motion.runner.robot_link_ros.RobotLink on a real robot or, under lockstep,
rbx1_nav.sim_time.course_member_ros.MemberClock and MemberLink, which do not
subclass them (sim_time imports nothing of motion). The runner cannot tell
them apart: each answers every question its twin does, with the same
arguments."""
import inspect

import pytest

from rbx1_nav.motion.runner.clock_ros import RateClock
from rbx1_nav.motion.runner.robot_link_ros import RobotLink
from rbx1_nav.sim_time.course_member_ros import MemberClock, MemberLink


def _questions(cls):
    """{public name: its parameters (methods) or its value (class attributes)}."""
    found = {}
    for name, value in vars(cls).items():
        if name.startswith('_'):
            continue
        found[name] = (list(inspect.signature(value).parameters) if callable(value)
                       else type(value))
    return found


@pytest.mark.parametrize('plain, member', [(RateClock, MemberClock), (RobotLink, MemberLink)])
def test_both_variants_answer_the_same_questions_with_the_same_arguments(plain, member):
    plain, member = _questions(plain), _questions(member)
    assert set(plain) == set(member), sorted(set(plain) ^ set(member))
    for name in plain:
        assert plain[name] == member[name], name


def test_a_clock_says_when_ticks_come_and_a_link_what_goes_to_and_from_the_robot():
    assert set(_questions(RateClock)) == {'start', 'ticks', 'pause', 'leave'}
    assert set(_questions(RobotLink)) == {
        'counts_commands', 'publisher', 'sent', 'takers', 'not_taken', 'arrived', 'take',
        'looks', 'reading'}


def test_only_the_lockstep_link_counts_the_commands():
    assert RobotLink.counts_commands is False and MemberLink.counts_commands is True
