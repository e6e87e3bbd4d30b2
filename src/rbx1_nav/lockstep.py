"""Lockstep simulated time: the clock waits for the slowest member.

Under free-running simulated time a node that falls behind the clock (a
busy CPU, a high ``sim_speed``) sees the robot move further between its
control ticks than it planned, so a course's result depends on the
scheduler. In lockstep, as with Webots' synchronised controllers or
Gazebo's lockstep, simulated time advances only when everyone taking part
has handled the step it asked for; then it runs as fast as the machine
allows (or as ``sim_speed`` caps it), and a course ends in the same pose at
any speed and under any load.

The protocol has two levels, each a :class:`Gate`:

* A **motion node** reports to its **simulator** (topic ``lockstep`` in the
  robot's namespace) after each control tick: the time it handled, the time
  of its next tick, and how many ``cmd_vel`` messages it has published since
  it joined. The simulator steps and publishes its state at every time a
  member asked for (so the node steers by the pose of that very instant),
  and lets time go on only once each member has reported and each of its
  commands has arrived (they travel on another connection, so the count
  puts the two streams back in order).
* A **simulator** reports to **sim_clock** (global topic ``/clock_lockstep``,
  one clock for every robot) after each step it made: the clock publishes a
  time only when no simulator's next step comes before it.

A motion node joins through its simulator's ``lockstep_join`` service,
which answers right after a step: the node's first tick is that step, and
the simulator already waits for it. A simulator joins the clock with its
first report. A member leaves with a report whose next time is 0, or when
its connection closes (the node died). Times are integer
nanoseconds; no rospy here, so the rules are unit-tested without a master.
"""

__all__ = ['Gate', 'Member', 'LEAVING']

#: The next tick of a member that is leaving (after its last commands).
LEAVING = 2 ** 63 - 1


class Member(object):
    """What a gate knows of one member: its last report and its commands."""

    __slots__ = ('handled', 'next', 'commands', 'received')

    def __init__(self):
        self.handled = self.next = None
        self.commands = 0   # commands it says it has sent since joining
        self.received = 0   # commands that have arrived from it

    def __repr__(self):
        return 'Member(handled=%r, next=%r, commands=%r, received=%r)' % (
            self.handled, self.next, self.commands, self.received)


class Gate(object):
    """The members of one lockstep level and how far time may go for them."""

    def __init__(self):
        self.members = {}  # name -> Member

    def report(self, name, handled, next_time, commands=0):
        """Take a member's report; return 'joined', 'left' or None.

        ``next_time`` 0 (or None) means the member leaves; it still holds
        time until the commands it reported have arrived.
        """
        member = self.members.get(name)
        if member is None:
            if not next_time:
                return None
            member = self.members[name] = Member()
            change = 'joined'
        else:
            change = None if next_time else 'left'
        member.handled, member.commands = handled, commands
        member.next = next_time or LEAVING
        self._sweep()
        return change

    def admit(self, name, time):
        """Make ``name`` a member that must handle ``time`` first (its join,
        granted at a step the simulator just published); True if new."""
        joined = name not in self.members
        member = self.members[name] = Member()
        member.next = time
        return joined

    def command_from(self, name):
        """Count a cmd_vel message that arrived from ``name``.

        Messages from non-members (teleop, a test) do not gate anything.
        """
        member = self.members.get(name)
        if member is not None:
            member.received += 1
            self._sweep()

    def missing_commands(self, time):
        """Names of the members that hold ``time`` back only for commands
        that have not arrived."""
        return sorted(name for name, m in self.members.items()
                      if time <= m.next and m.received < m.commands)

    def forgive(self, name):
        """Stop waiting for ``name``'s missing commands (lost on the way)."""
        member = self.members[name]
        member.received = member.commands
        self._sweep()

    def _sweep(self):
        """Forget members that left once their last commands arrived."""
        for name in [name for name, m in self.members.items()
                     if m.next == LEAVING and m.received >= m.commands]:
            del self.members[name]

    def leave(self, name):
        """Forget ``name`` (it left or its connection closed); True if known."""
        return self.members.pop(name, None) is not None

    def keep_only(self, names):
        """Drop every member not in ``names``; return the names dropped."""
        gone = sorted(set(self.members) - set(names))
        for name in gone:
            del self.members[name]
        return gone

    def blocking(self, time):
        """Names of the members that keep simulated time from reaching ``time``.

        A member blocks while ``time`` is past its next tick (it must handle
        that tick and report first), or while commands it reported sending
        have not all arrived.
        """
        return sorted(name for name, m in self.members.items()
                      if time > m.next or m.received < m.commands)

    def allows(self, time):
        """True when simulated time may reach ``time``."""
        return not self.blocking(time)

    def next_tick(self):
        """The earliest next tick of any member, or None if none has one."""
        return min((m.next for m in self.members.values() if m.next != LEAVING),
                   default=None)
