"""The seam that keeps simulated time out of motion/: a course's clock is
rbx1_nav.motion.ticks_ros.Ticks on a real robot, or, under lockstep,
rbx1_nav.sim_time.course_member_ros.MemberTicks, which does not subclass it
(sim_time imports nothing of motion). The runner cannot tell them apart:
each answers every question the other does, with the same arguments."""
import inspect

from rbx1_nav.motion.ticks_ros import Ticks
from rbx1_nav.sim_time.course_member_ros import MemberTicks


def _questions(cls):
    """{public name: its parameters (methods) or its value (class attributes)}."""
    found = {}
    for name, value in vars(cls).items():
        if name.startswith('_'):
            continue
        found[name] = (list(inspect.signature(value).parameters) if callable(value)
                       else type(value))
    return found


def test_both_clocks_answer_the_same_questions_with_the_same_arguments():
    plain, member = _questions(Ticks), _questions(MemberTicks)
    assert set(plain) == set(member), sorted(set(plain) ^ set(member))
    for name in plain:
        assert plain[name] == member[name], name


def test_only_the_lockstep_clock_counts_the_commands():
    assert Ticks.counts_commands is False and MemberTicks.counts_commands is True
