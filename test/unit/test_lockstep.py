"""rbx1_nav.sim_time.lockstep: one owner grants every step, and nothing can wait forever.

The first tests check the rules one at a time. The last ones run a whole
lockstep graph (an owner, a simulator and motion nodes) in plain Python,
with every message a separate delivery whose order and delay are chosen
by a seeded random scheduler: injected delays at every hand-off (the 3 ms
one of the old design among them), a member that dies between grant and
reply, members joining and leaving mid-step, and an owner restarted from
further back. Each run must make progress to the end, and the simulator
must apply every command at the tick it was sent for.
"""
import random

import pytest

from rbx1_nav.sim_time.lockstep import Owner
from rbx1_nav.sim_time.member import (ALIGN, BACK, HANDLE, NO_TICK, REPEAT, STALE,
                                      Follower, Inbox, MessageLedger, Report, Reminder, aligned)

MS = 1000000  # ns
SIM = {'/sim'}  # a grant's members: the simulator, granted every step


def report(name, handled, next_time, every_step=False, sent=None, leaving=False,
           passive=False):
    return Report(name, handled, next_time, every_step, sent or {}, leaving, passive)


# -- Owner ---------------------------------------------------------------

def test_without_members_nothing_is_granted():
    assert Owner().next_grant() is None


def test_a_joining_member_gets_the_next_step_whatever_it_asked():
    owner = Owner(start=40 * MS, step=10 * MS)
    assert owner.report(report('/sim', 0, 999 * MS, every_step=True)) == ('joined', None)
    assert owner.next_grant() == (50 * MS, ['/sim'])


def test_time_jumps_to_the_earliest_tick_and_grants_only_those_due():
    owner = Owner()
    owner.report(report('/sim', 0, 0, every_step=True))
    owner.report(report('/course', 0, 0))
    time, names = owner.next_grant()
    assert names == ['/course', '/sim']
    owner.grant(time, names)
    owner.report(report('/sim', time, time + 20 * MS, every_step=True))
    assert owner.owing() == ['/course']
    owner.report(report('/course', time, time + 50 * MS))
    # The simulator's grid comes first; the course is not granted it.
    assert owner.next_grant() == (time + 20 * MS, ['/sim'])


def test_grants_name_the_simulators_not_the_filters():
    """A filter granted every step until its first estimate is still no
    simulator: a course following its transform must not wait for a
    state stamped at each tick from it."""
    owner = Owner()
    owner.report(report('/sim', 0, 0, every_step=True))
    owner.report(report('/robot_pose_ekf', 0, 0))
    owner.report(report('/course', 0, 0))
    assert owner.simulators() == ['/sim']


def test_a_20_hz_course_on_a_50_hz_simulator_costs_only_their_ticks():
    owner = Owner()
    owner.report(report('/sim', 0, 0, every_step=True))
    owner.report(report('/course', 0, 0))
    grid, times, ticks = None, [], []
    while owner.now < 1010 * MS:
        time, names = owner.next_grant()
        owner.grant(time, names)
        times.append(time)
        if grid is None or time >= grid:
            grid = time + 20 * MS
        owner.report(report('/sim', time, grid, every_step=True))
        if '/course' in names:
            ticks.append(time)
            owner.report(report('/course', time, time + 50 * MS))
    # From the first step (10 ms): the simulator's 50 Hz grid and the
    # course's 20 Hz ticks, one step where they meet: 60 a second, where
    # a 10 ms walk takes 100.
    second = [t for t in times if 10 * MS < t <= 1010 * MS]
    assert len(second) == 60
    assert ticks == list(range(10 * MS, 1010 * MS + 1, 50 * MS))
    assert set(range(10 * MS, 1010 * MS + 1, 20 * MS)) <= set(times)


def test_a_course_starts_on_a_multiple_of_align_whenever_it_joined():
    """Its 20 Hz ticks then meet a 50 Hz grid from zero at the same
    offsets every time (ALIGN is a multiple of both periods and of the
    10 ms clock step)."""
    assert [aligned(t) for t in (0, 1, 10 * MS, ALIGN, ALIGN + 10 * MS)] == [
        0, ALIGN, ALIGN, ALIGN, 2 * ALIGN]
    assert ALIGN % (20 * MS) == ALIGN % (50 * MS) == ALIGN % (10 * MS) == 0


def test_a_filter_follows_time_without_driving_it():
    """With only simulators and filters taking part, sim_clock at full
    speed idles: nothing waits for the time a filter spends."""
    owner = Owner()
    owner.report(report('/sim', 0, 0, every_step=True))
    owner.report(report('/ekf', 0, 0, passive=True))
    assert not owner.drives()
    owner.report(report('/course', 0, 0))
    assert owner.drives()


def test_batched_a_simulator_is_granted_only_the_courses_ticks():
    owner = Owner(batch=True)
    owner.report(report('/sim', 0, 0, every_step=True))
    time, names = owner.next_grant()
    owner.grant(time, names)
    owner.report(report('/sim', time, time + 20 * MS, every_step=True))
    assert owner.next_grant() == (time + 20 * MS, ['/sim'])  # alone: its grid
    owner.report(report('/course', 0, 0))
    time, names = owner.next_grant()
    owner.grant(time, names)
    owner.report(report('/sim', time, time + 20 * MS, every_step=True))
    owner.report(report('/course', time, time + 50 * MS))
    assert owner.next_grant() == (time + 50 * MS, ['/course', '/sim'])
    owner.report(report('/course', 0, 0, leaving=True))
    assert owner.next_grant() == (time + 20 * MS, ['/sim'])


def test_reports_that_do_not_answer_the_grant_change_nothing():
    owner = Owner()
    owner.report(report('/course', 0, 0))
    owner.grant(10 * MS, ['/course'])
    assert owner.report(report('/course', 0, 0)) == (None, None)  # join again
    assert owner.report(report('/course', 5 * MS, 60 * MS)) == (None, None)
    assert owner.owing() == ['/course']
    owner.report(report('/course', 10 * MS, 60 * MS))
    assert owner.owing() == []
    owner.report(report('/course', 10 * MS, 60 * MS))  # sent again
    assert owner.next_grant() == (60 * MS, ['/course'])


def test_a_next_tick_not_after_the_step_handled_is_refused_with_a_warning():
    owner = Owner(step=10 * MS)
    owner.report(report('/course', 0, 0))
    owner.grant(10 * MS, ['/course'])
    change, warning = owner.report(report('/course', 10 * MS, 5 * MS))
    assert change is None and 'refused' in warning and '/course' in warning
    assert owner.next_grant() == (20 * MS, ['/course'])


def test_a_member_without_a_tick_of_its_own_is_granted_whatever_comes_next():
    """A filter waiting for its first data (next NO_TICK) follows the
    others' ticks: a bag player's next message, without steps between."""
    owner = Owner(start=0, step=10 * MS)
    owner.report(report('/player', 0, 0))
    owner.report(report('/ekf', 0, 0))
    time, names = owner.next_grant()
    owner.grant(time, names)
    owner.report(report('/player', time, 5000 * MS))
    assert owner.report(report('/ekf', time, NO_TICK)) == (None, None)
    assert owner.next_grant() == (5000 * MS, ['/ekf', '/player'])


def test_a_grant_in_the_past_is_an_error_of_the_owner():
    owner = Owner(start=10 * MS)
    owner.report(report('/course', 0, 0))
    with pytest.raises(ValueError):
        owner.grant(10 * MS, ['/course'])


def test_the_owner_waits_for_a_silent_member_and_skips_those_gone():
    owner = Owner()
    owner.report(report('/a', 0, 0))
    owner.report(report('/b', 0, 0))
    owner.report(report('/c', 0, 0))
    owner.report(report('/c', 0, 0, leaving=True))  # left before the grant
    assert owner.grant(10 * MS, ['/a', '/b', '/c']) == ['/a', '/b']
    owner.report(report('/a', 10 * MS, 20 * MS))
    assert owner.owing() == ['/b']  # time waits for it: no next step
    assert owner.drop('/b') and not owner.drop('/b')  # its connection closed
    assert owner.owing() == [] and owner.next_grant() == (20 * MS, ['/a'])


def test_command_counts_outlive_a_member_that_left():
    owner = Owner()
    owner.report(report('/course', 0, 0, sent={'/cmd_vel': 3}))
    assert owner.report(report('/course', 0, 0, leaving=True,
                               sent={'/cmd_vel': 4})) == ('left', None)
    assert owner.sent_counts() == [('/cmd_vel', '/course', 4)]
    assert owner.next_grant() is None


# -- Follower -------------------------------------------------------------

def test_a_follower_handles_new_steps_repeats_old_ones_and_refuses_stale():
    follower = Follower()
    assert follower.grant(7, 10 * MS) == HANDLE
    follower.handled_step(10 * MS)
    assert follower.grant(7, 10 * MS) == REPEAT
    assert follower.grant(7, 5 * MS) == STALE
    assert follower.grant(7, 20 * MS) == HANDLE


def test_a_new_owner_from_further_back_is_time_moving_back():
    follower = Follower()
    follower.grant(1, 30 * MS)
    follower.handled_step(30 * MS)
    assert follower.grant(2, 10 * MS) == BACK
    follower.handled_step(10 * MS)
    assert follower.grant(2, 20 * MS) == HANDLE


# -- MessageLedger and Inbox ----------------------------------------------

def test_the_ledger_waits_only_for_its_own_topics():
    ledger = MessageLedger(['/robot1/cmd_vel'])
    counts = [('/robot1/cmd_vel', '/course1', 2), ('/robot2/cmd_vel', '/course2', 5)]
    assert ledger.missing(counts) == [('/robot1/cmd_vel', '/course1', 2)]
    ledger.arrived('/robot1/cmd_vel', '/course1')
    ledger.arrived('/robot1/cmd_vel', '/teleop')  # not counted by anyone
    assert ledger.missing(counts) == [('/robot1/cmd_vel', '/course1', 1)]
    ledger.arrived('/robot1/cmd_vel', '/course1')
    assert ledger.missing(counts) == []


def test_commands_lost_on_the_way_are_given_up_once():
    ledger = MessageLedger(['/cmd_vel'])
    ledger.arrived('/cmd_vel', '/course')
    counts = [('/cmd_vel', '/course', 3)]
    assert ledger.give_up(counts) == [('/cmd_vel', '/course', 2)]
    assert ledger.missing(counts) == []
    ledger.arrived('/cmd_vel', '/course')
    assert ledger.missing([('/cmd_vel', '/course', 4)]) == []


def test_a_simulator_started_late_does_not_wait_for_earlier_commands():
    ledger = MessageLedger(['/cmd_vel'])
    ledger.arrived('/cmd_vel', '/course')  # one sent after it listened
    ledger.settle([('/cmd_vel', '/course', 120), ('/other/cmd_vel', '/x', 5)])
    assert ledger.missing([('/cmd_vel', '/course', 120)]) == []
    assert ledger.missing([('/cmd_vel', '/course', 121)]) == [('/cmd_vel', '/course', 1)]
    ledger.arrived('/cmd_vel', '/course')
    assert ledger.missing([('/cmd_vel', '/course', 121)]) == []


def test_a_sender_started_again_under_its_name_is_waited_for_from_its_first():
    ledger = MessageLedger(['/cmd_vel'])
    for _ in range(120):
        ledger.arrived('/cmd_vel', '/umbmark')
    ledger.restarts([('/cmd_vel', '/umbmark', 120)])
    assert ledger.missing([('/cmd_vel', '/umbmark', 120)]) == []
    ledger.restarts([('/cmd_vel', '/umbmark', 2)])  # the new /umbmark's count
    assert ledger.missing([('/cmd_vel', '/umbmark', 2)]) == [('/cmd_vel', '/umbmark', 2)]
    ledger.arrived('/cmd_vel', '/umbmark')
    ledger.arrived('/cmd_vel', '/umbmark')
    assert ledger.missing([('/cmd_vel', '/umbmark', 2)]) == []


def test_a_restarted_simulator_waits_for_a_restarted_sender():
    """The grant still shows the old sender's count when the simulator
    joins (settled as sent before it listened); then the new one's."""
    ledger = MessageLedger(['/cmd_vel'])
    ledger.settle([('/cmd_vel', '/umbmark', 120)])
    ledger.restarts([('/cmd_vel', '/umbmark', 120)])
    ledger.restarts([('/cmd_vel', '/umbmark', 1)])
    assert ledger.missing([('/cmd_vel', '/umbmark', 1)]) == [('/cmd_vel', '/umbmark', 1)]
    inbox = Inbox(['/odom'])
    inbox.arrived('/odom', '/sim', 'old')
    inbox.ledger.restarts([('/odom', '/sim', 1)])
    assert inbox.take([('/odom', '/sim', 1)], SIM, key=str) == ['old']
    inbox.arrived('/odom', '/sim', 'new')
    inbox.ledger.restarts([('/odom', '/sim', 1)])  # not a drop: the same count
    inbox.ledger.restarts([('/odom', '/sim', 0)])
    inbox.ledger.restarts([('/odom', '/sim', 1)])
    assert inbox.take([('/odom', '/sim', 1)], SIM, key=str) == ['new']


def test_a_restarted_sender_is_counted_on_its_new_connection_only():
    """The old node's stop sent after its last report (it had left) comes
    on the old connection: not taken for one of the new node's commands,
    which the simulator must wait for."""
    ledger = MessageLedger(['/cmd_vel'])
    for _ in range(5):
        ledger.arrived('/cmd_vel', '/course', link=1)
    ledger.restarts([('/cmd_vel', '/course', 5)])
    ledger.arrived('/cmd_vel', '/course', link=1)  # its stop after leaving
    ledger.arrived('/cmd_vel', '/course', link=2)  # the new node's first
    ledger.restarts([('/cmd_vel', '/course', 2)])
    assert ledger.missing([('/cmd_vel', '/course', 2)]) == [('/cmd_vel', '/course', 1)]
    ledger.arrived('/cmd_vel', '/course', link=2)
    assert ledger.missing([('/cmd_vel', '/course', 2)]) == []
    # A third node under the name, after a second shorter than the first.
    ledger.arrived('/cmd_vel', '/course', link=2)  # the second's late stop
    ledger.arrived('/cmd_vel', '/course', link=3)
    ledger.restarts([('/cmd_vel', '/course', 1)])
    assert ledger.missing([('/cmd_vel', '/course', 1)]) == []
    assert ledger.missing([('/cmd_vel', '/course', 2)]) == [('/cmd_vel', '/course', 1)]


def test_the_inbox_gives_only_what_the_grant_counts_in_stamp_order():
    """A message published during the step being handled may have arrived
    or not: taken only once a grant counts it, so every run reads the same."""
    inbox = Inbox(['/odom', '/imu'])
    inbox.arrived('/odom', '/sim', 1.0)
    inbox.arrived('/imu', '/sim', 0.5)
    inbox.arrived('/odom', '/sim', 2.0)  # sent after the reports of this grant
    counts = [('/odom', '/sim', 1), ('/imu', '/sim', 1), ('/cmd_vel', '/x', 9)]
    assert inbox.ledger.missing(counts) == []
    assert inbox.take(counts, SIM, key=float) == [0.5, 1.0]
    assert inbox.take(counts, SIM, key=float) == []  # nothing new counted
    assert inbox.take([('/odom', '/sim', 2)], SIM, key=float) == [2.0]


def test_the_inbox_gives_one_input_and_keeps_the_others_for_their_reader():
    """A course reads /tf in its transform follower and odom in its stall
    watch: each takes its own topic's counted messages, the other's stay."""
    inbox = Inbox(['/tf', '/odom'])
    inbox.arrived('/odom', '/sim', 1.0)
    inbox.arrived('/tf', '/sim', 1.5)
    counts = [('/odom', '/sim', 1), ('/tf', '/sim', 1)]
    assert inbox.take(counts, SIM, key=float, topic='/tf') == [1.5]
    assert inbox.take(counts, SIM, key=float, topic='/tf') == []
    assert inbox.take(counts, SIM, key=float, topic='/odom') == [1.0]


def test_the_inbox_takes_uncounted_senders_as_they_come_and_skips_the_lost():
    inbox = Inbox(['/odom'])
    inbox.arrived('/odom', '/rosbag_play', 'free')  # no member: no count
    inbox.arrived('/odom', '/sim', 'a')
    counts = [('/odom', '/sim', 3)]
    assert inbox.ledger.give_up(counts) == [('/odom', '/sim', 2)]
    assert inbox.take(counts, SIM, key=str) == ['a', 'free']


def test_a_members_first_messages_wait_for_the_grant_that_counts_them():
    # A simulator's state arrives before any report of it counted a
    # message on that topic: taken as it came, what a filter got would
    # depend on the arrival (ekf_out_and_back differed from run to run).
    inbox = Inbox(['/odom'])
    inbox.arrived('/odom', '/sim', 'early')
    assert inbox.take([], SIM, key=str) == []
    assert inbox.take([('/odom', '/sim', 1)], SIM, key=str) == ['early']
    inbox.arrived('/odom', '/rosbag_play', 'free')  # no member: as it comes
    assert inbox.take([], SIM, key=str) == ['free']


def test_a_simulator_holds_a_command_sent_during_its_step_until_it_is_counted():
    # A course granted the step a simulator handles may command before
    # the simulator has stepped there (it follows a filter's transform,
    # not the simulator's state): the command waits for the next grant,
    # whatever the order (ekf_out_and_back's /ekf robot got its commands
    # 10 ms early or on time from run to run).
    inbox = Inbox(['/cmd_vel'])
    inbox.arrived('/cmd_vel', '/course', 'counted')
    inbox.arrived('/cmd_vel', '/course', 'sent at this step')
    granted = {'/sim', '/course'}
    assert inbox.take([('/cmd_vel', '/course', 1)], granted, key=str) == ['counted']
    assert inbox.take([('/cmd_vel', '/course', 2)], SIM, key=str) == ['sent at this step']
    # Its stop on its way out, past its last count (it has left): as it comes.
    inbox.arrived('/cmd_vel', '/course', 'stop')
    assert inbox.take([('/cmd_vel', '/course', 2)], SIM, key=str) == ['stop']


def test_the_inbox_of_a_late_member_takes_what_it_heard_before_its_first_grant():
    inbox = Inbox(['/odom'])
    inbox.arrived('/odom', '/sim', 'heard')
    counts = [('/odom', '/sim', 40)]  # 39 sent before it listened
    inbox.ledger.settle(counts)
    assert inbox.take(counts, SIM, key=str) == ['heard']
    inbox.arrived('/odom', '/sim', 'next')
    assert inbox.take([('/odom', '/sim', 41)], SIM, key=str) == ['next']


def test_messages_passed_while_not_a_member_are_counted_not_kept():
    inbox = Inbox(['/tf'])
    for _ in range(3):
        inbox.passed('/tf', '/ekf')  # before the course joined
    inbox.arrived('/tf', '/ekf', 'kept')
    assert sum(len(q) for q in inbox.held.values()) == 1
    assert inbox.take([('/tf', '/ekf', 3)], {'/ekf'}, key=str) == []
    assert inbox.take([('/tf', '/ekf', 4)], {'/ekf'}, key=str) == ['kept']


# -- A whole graph, with messages delayed and reordered ----------------------

class Network(object):
    """Messages in flight, each on its own connection (a FIFO per sender
    and receiver, as TCP gives), delivered in an order a seeded random
    scheduler picks: any connection may lag any other by any amount."""

    def __init__(self, rng, slow=None):
        self.rng = rng
        self.slow = slow  # (src, dst): delivered only when nothing else is
        self.queues = {}  # (src, dst) -> [message]

    def send(self, src, dst, message):
        self.queues.setdefault((src, dst), []).append(message)

    def deliver_one(self):
        busy = [key for key, queue in self.queues.items() if queue]
        if not busy:
            return False
        if len(busy) > 1 and self.slow in busy:
            busy.remove(self.slow)
        key = self.rng.choice(sorted(busy))
        dst = key[1]
        message = self.queues[key].pop(0)
        dst_node = self.nodes.get(dst)
        if dst_node is not None:
            dst_node.receive(key[0], message)
        return True

    def drop_node(self, name):
        self.nodes.pop(name, None)
        for key in list(self.queues):
            if name in key:
                del self.queues[key]


class OwnerNode(object):
    """sim_clock in miniature: grants, waits, drops the dead."""

    def __init__(self, net, session, start=0):
        self.net, self.session = net, session
        self.owner = Owner(start=start, step=10 * MS)
        self.granted = None

    def receive(self, src, message):
        self.owner.report(message)

    def tick(self):
        """Grant the next step once nobody owes a report."""
        if self.granted is not None and self.owner.owing():
            return
        grant = self.owner.next_grant()
        if grant is None:
            return
        time, names = grant
        names = self.owner.grant(time, names)
        self.granted = time
        counts = self.owner.sent_counts()
        for name in list(self.net.nodes):
            if name != 'owner':
                self.net.send('owner', name, ('grant', self.session, time, names, counts))

    def dead(self, name):
        self.owner.drop(name)


class SimNode(object):
    """A simulator: steps at every grant once the counted commands arrived."""

    def __init__(self, net, name='/sim', period=20 * MS):
        self.net, self.name, self.period = net, name, period
        self.follower = Follower()
        self.ledger = MessageLedger(['cmd_vel'])
        self.waiting = None   # a grant held until its commands arrive
        self.command = None   # (value, time it was sent for)
        self.applied = []     # (step time, command value, sent for)
        self.state = {}       # step time -> published
        self.grid = None
        self.backs = 0

    def join(self):
        self.net.send(self.name, 'owner', report(self.name, 0, 0, every_step=True))

    def receive(self, src, message):
        if message[0] == 'grant':
            _, session, time, names, counts = message
            if self.name in names:
                self.waiting = (session, time, counts)
        else:  # a command
            _, value, sent_for = message
            self.ledger.arrived('cmd_vel', src)
            self.command = (value, sent_for)
        self.try_step()

    def try_step(self):
        if self.waiting is None:
            return
        session, time, counts = self.waiting
        if self.ledger.missing(counts):
            return  # its commands are still on their way
        self.waiting = None
        action = self.follower.grant(session, time)
        if action in (REPEAT, STALE):
            return
        if action == BACK:
            self.backs += 1
            self.grid = None
        self.applied.append((time, self.command))
        self.state[time] = True
        for node in self.net.nodes.values():
            if isinstance(node, CourseNode):
                node.state_published(time)
        self.follower.handled_step(time)
        if self.grid is None or time >= self.grid:
            self.grid = time + self.period
        self.net.send(self.name, 'owner', report(self.name, time, self.grid, every_step=True))


class CourseNode(object):
    """A motion node: at each of its ticks, waits for the simulator's state
    of that time if the simulator was granted it too, sends one command,
    reports."""

    def __init__(self, net, name, period=50 * MS, ticks=40):
        self.net, self.name, self.period, self.left_ticks = net, name, period, ticks
        self.follower = Follower()
        self.sent = 0
        self.pending = None
        self.published = set()
        self.ticks = []
        self.backs = 0
        self.done = False

    def join(self):
        self.net.send(self.name, 'owner', report(self.name, 0, 0))

    def state_published(self, time):
        # The simulator's state travels on its own connection.
        self.net.send('/sim', self.name, ('state', time))

    def receive(self, src, message):
        if message[0] == 'state':
            self.published.add(message[1])
        elif message[0] == 'grant' and self.name in message[3]:
            self.pending = message[1], message[2], '/sim' in message[3]
        self.try_tick()

    def try_tick(self):
        if self.pending is None or self.done:
            return
        session, time, sim_granted = self.pending
        if sim_granted and time not in self.published:
            return  # the simulator's state at this tick is on its way
        self.pending = None
        action = self.follower.grant(session, time)
        if action == BACK:
            self.backs += 1
            self.leave()
            return
        if action != HANDLE:
            return
        self.follower.handled_step(time)
        self.ticks.append(time)
        self.sent += 1
        self.net.send(self.name, '/sim', ('cmd', self.name, time))
        self.left_ticks -= 1
        if self.left_ticks == 0:
            self.leave()
            return
        self.net.send(self.name, 'owner', report(self.name, time, time + self.period,
                                                 sent={'cmd_vel': self.sent}))

    def leave(self):
        self.done = True
        self.net.send(self.name, 'owner', report(self.name, 0, 0, leaving=True,
                                                 sent={'cmd_vel': self.sent}))


def run_graph(seed, courses=2, kill=None, late_join=None, restart_at=None,
              slow=None, limit=200000):
    """Run the graph until every course is done; return the owner, the
    simulator, the courses and how often a wall-time watchdog had to act
    (nothing in flight, yet a report owed)."""
    rng = random.Random(seed)
    net = Network(rng, slow)
    owner = OwnerNode(net, session=1)
    sim = SimNode(net)
    nodes = [CourseNode(net, '/course%d' % i) for i in range(courses)]
    net.nodes = {'owner': owner, '/sim': sim}
    sim.join()
    # A course joins once it has seen its simulator in a grant (the
    # runner's start-up waits for that).
    joining = list(nodes if late_join is None else nodes[:-1])
    watchdogs = 0
    for _ in range(limit):
        if joining and sim.follower.handled is not None:
            for node in joining:
                net.nodes[node.name] = node
                node.join()
            joining = []
        if all(node.done for node in nodes) and sim.follower.session == owner.session:
            return owner, sim, nodes, watchdogs
        if kill and owner.owner.now >= kill[1] and kill[0] in net.nodes:
            # Dies between grant and reply; the owner sees its connection close.
            net.drop_node(kill[0])
            owner.dead(kill[0])
            next(node for node in nodes if node.name == kill[0]).done = True
        if late_join is not None and owner.owner.now >= late_join and nodes[-1].name not in net.nodes:
            net.nodes[nodes[-1].name] = nodes[-1]
            nodes[-1].join()
        if restart_at is not None and owner.owner.now >= restart_at:
            restart_at = None
            # A new owner, started further back; the members' reports
            # (sent again after RESEND in the ROS side) make them join it.
            net.drop_node('owner')  # it died: its connections closed
            owner = OwnerNode(net, session=2, start=owner.owner.now - 100 * MS)
            net.nodes['owner'] = owner
            sim.join()
            for node in nodes:
                if not node.done:
                    node.join()
        # Deliver a random number of messages, then let the owner act: a
        # random interleaving of every hand-off.
        delivered = [net.deliver_one() for _ in range(rng.randint(0, 3))]
        if not any(delivered) and not any(net.queues.values()) and owner.owner.owing():
            # Stuck until a watchdog acts: here only commands that died
            # with their sender can be missing (LOST_MESSAGES).
            watchdogs += 1
            assert sim.waiting is not None, 'stuck with nothing to wait for'
            sim.ledger.give_up(sim.waiting[2])
            sim.try_step()
        owner.tick()
    raise AssertionError('the graph stopped at %.3f s' % (owner.owner.now * 1e-9))


def commands_applied_at_their_tick(sim, node):
    """Each of the node's commands took effect from the step after its
    tick, never later: the simulator waited for it."""
    ticks = set(node.ticks)
    for time, command in sim.applied:
        if command is not None and command[0] == node.name:
            assert command[1] < time
    for tick in node.ticks:
        later = [(time, command) for time, command in sim.applied if time > tick]
        if later and later[0][1] is not None and later[0][1][0] == node.name:
            assert later[0][1][1] >= tick
    return ticks


@pytest.mark.parametrize('seed', range(40))
def test_any_delivery_order_reaches_the_end(seed):
    owner, sim, nodes, watchdogs = run_graph(seed)
    assert watchdogs == 0
    for node in nodes:
        assert len(node.ticks) == 40
        # Every tick a multiple of its period from its first: none skipped.
        assert all(b - a == 50 * MS for a, b in zip(node.ticks, node.ticks[1:]))
        commands_applied_at_their_tick(sim, node)
    # The simulator stepped at each course tick (its state was there).
    assert set(nodes[0].ticks) <= set(sim.state)


def test_a_single_course_sees_each_command_applied_on_the_next_step():
    owner, sim, (node,), _ = run_graph(3, courses=1)
    by_time = dict(sim.applied)
    for tick in node.ticks[:-1]:
        nxt = min(time for time in by_time if time > tick)
        assert by_time[nxt] == (node.name, tick)


@pytest.mark.parametrize('seed', range(10))
def test_a_member_that_dies_between_grant_and_reply_is_dropped(seed):
    owner, sim, nodes, _ = run_graph(seed, kill=('/course0', 500 * MS))
    assert len(nodes[0].ticks) < 40 and len(nodes[1].ticks) == 40
    assert '/course0' not in owner.owner.members


@pytest.mark.parametrize('seed', range(10))
def test_a_member_joining_mid_course_gets_the_next_step(seed):
    owner, sim, nodes, watchdogs = run_graph(seed, courses=3, late_join=777 * MS)
    assert watchdogs == 0
    late = nodes[-1]
    assert len(late.ticks) == 40 and late.ticks[0] > 777 * MS
    commands_applied_at_their_tick(sim, late)


@pytest.mark.parametrize('seed', range(10))
def test_a_new_owner_from_further_back_moves_every_member_back(seed):
    owner, sim, nodes, watchdogs = run_graph(seed, restart_at=600 * MS)
    assert watchdogs == 0
    assert sim.backs == 1
    # The courses saw time move back and left (a course node aborts).
    assert all(node.backs == 1 for node in nodes)
    assert owner.session == 2 and owner.owner.now < 600 * MS + 100 * MS


HAND_OFFS = [('owner', '/sim'), ('owner', '/course0'), ('/sim', 'owner'),
             ('/course0', 'owner'), ('/course0', '/sim'), ('/sim', '/course0')]


@pytest.mark.parametrize('slow', HAND_OFFS, ids=['->'.join(h) for h in HAND_OFFS])
def test_a_hand_off_delayed_as_long_as_possible_only_delays_time(slow):
    """Each connection in turn holds its messages until nothing else can
    move (the 3 ms pause of the old design's deadlock, and any longer one):
    the graph still reaches the end, every command applied at its tick."""
    owner, sim, nodes, watchdogs = run_graph(5, slow=slow)
    assert watchdogs == 0
    for node in nodes:
        assert len(node.ticks) == 40
        commands_applied_at_their_tick(sim, node)


def test_a_member_nothing_grants_to_warns_once_then_once_a_minute():
    reminder = Reminder(5.0, 60.0, now=100.0)
    assert [reminder.due(t) for t in (100.0, 104.9)] == [None, None]
    assert reminder.due(105.0) == 5.0
    assert [reminder.due(t) for t in (110.0, 150.0, 164.9)] == [None, None, None]
    assert reminder.due(165.0) == 65.0
    reminder.granted(200.0)  # a grant ends the wait: the next one starts over
    assert reminder.due(204.0) is None and reminder.due(205.5) == 5.5
