"""rbx1_nav.lockstep.Gate: who holds simulated time, and until when."""
from rbx1_nav.lockstep import Gate

MS = 1000000  # ns


def test_without_members_time_is_free():
    gate = Gate()
    assert gate.allows(10 ** 18)
    assert gate.next_tick() is None


def test_time_may_reach_a_members_next_tick_but_not_pass_it():
    gate = Gate()
    assert gate.report('/course', 0, 50 * MS) == 'joined'
    assert gate.allows(50 * MS)
    assert not gate.allows(50 * MS + 1)
    assert gate.blocking(60 * MS) == ['/course']
    assert gate.report('/course', 50 * MS, 100 * MS) is None
    assert gate.allows(100 * MS)
    assert gate.next_tick() == 100 * MS


def test_the_slowest_member_decides():
    gate = Gate()
    gate.report('/a', 0, 20 * MS)
    gate.report('/b', 0, 50 * MS)
    assert gate.next_tick() == 20 * MS
    assert gate.blocking(30 * MS) == ['/a']
    assert gate.blocking(60 * MS) == ['/a', '/b']


def test_time_waits_for_every_reported_command():
    gate = Gate()
    gate.report('/course', 0, 50 * MS)
    gate.report('/course', 50 * MS, 100 * MS, commands=2)
    assert not gate.allows(60 * MS)  # both commands still on their way
    gate.command_from('/course')
    assert gate.blocking(60 * MS) == ['/course']
    gate.command_from('/course')
    assert gate.allows(60 * MS)


def test_commands_from_non_members_gate_nothing():
    gate = Gate()
    gate.command_from('/teleop')
    assert gate.allows(10 ** 12) and not gate.members


def test_a_leaving_member_holds_time_until_its_last_commands_arrive():
    gate = Gate()
    gate.report('/course', 0, 50 * MS)
    gate.command_from('/course')
    assert gate.report('/course', 50 * MS, 0, commands=2) == 'left'
    assert '/course' in gate.members and not gate.allows(60 * MS)
    assert gate.next_tick() is None  # it asks for no more ticks
    gate.command_from('/course')
    assert not gate.members and gate.allows(10 ** 12)


def test_rejoining_starts_the_command_count_afresh():
    gate = Gate()
    gate.report('/course', 0, 50 * MS)
    for _ in range(3):
        gate.command_from('/course')
    gate.report('/course', 50 * MS, 0, commands=3)
    assert not gate.members
    gate.report('/course', 80 * MS, 130 * MS, commands=1)
    assert not gate.allows(140 * MS)  # its new command has not arrived
    gate.command_from('/course')
    gate.report('/course', 130 * MS, 180 * MS, commands=1)
    assert gate.allows(180 * MS)


def test_a_report_for_a_stranger_who_leaves_changes_nothing():
    gate = Gate()
    assert gate.report('/ghost', 0, 0) is None
    assert not gate.members


def test_dead_members_are_dropped():
    gate = Gate()
    gate.report('/a', 0, 20 * MS)
    gate.report('/b', 0, 20 * MS)
    assert gate.keep_only(['/b', '/other']) == ['/a']
    assert list(gate.members) == ['/b']
    assert gate.leave('/b') and not gate.leave('/b')


def test_lost_commands_can_be_forgiven():
    gate = Gate()
    gate.report('/course', 50 * MS, 100 * MS, commands=3)
    gate.command_from('/course')
    assert gate.missing_commands(60 * MS) == ['/course']
    assert gate.missing_commands(110 * MS) == []  # it owes a report too
    gate.forgive('/course')
    assert gate.allows(100 * MS)


def test_an_admitted_node_holds_time_at_its_first_tick():
    gate = Gate()
    assert gate.admit('/course', 40 * MS)
    assert gate.allows(40 * MS) and not gate.allows(40 * MS + 1)
    gate.command_from('/course')  # its first command, counted at once
    assert gate.report('/course', 40 * MS, 90 * MS, commands=1) is None
    assert gate.allows(90 * MS)
