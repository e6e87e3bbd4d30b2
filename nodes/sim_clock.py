#!/usr/bin/env python3
"""sim_clock: publish /clock at ~speed times real time, for /use_sim_time runs.

One clock serves every robot on the master, so it publishes the global
/clock topic. This is the only node that reads the wall clock; every other
node follows the simulated time it publishes, so tests run the same at 1x
and at 20x. The pacing itself is rbx1_nav.sim_time.pacer.ClockPacer.

With the global parameter /lockstep true (sim_clock.launch lockstep:=true),
this node is the one owner of simulated time (rbx1_nav.sim_time.lockstep): it
grants each step to the simulators and the motion nodes taking part and
waits until each has handled it, jumping from one member's tick to the
next; a course then ends the same at any speed and under any load.
~speed max runs as fast as they allow while a motion node takes part;
with only simulators taking part (a course not started yet, or over) it
runs at ~idle_speed, so a waiting simulator does not spin a core for
nothing; with nobody taking part, at real time.

A clock already running under this node's name is left alone: this one
says so and exits 0 before it registers (the master would shut the
running one down).

Publishes:  /clock (rosgraph_msgs/Clock), /lockstep_grant
            (rbx1_nav/LockstepGrant, under /lockstep)
Subscribes: /lockstep_report (rbx1_nav/LockstepReport, under /lockstep)
sim_clock.launch sets ~speed from its arg sim_speed (a number, or max),
~members from members and the global /lockstep from lockstep (true), and
/use_sim_time; with ~clear_sim_time (its launch's) this node removes both
as that roslaunch ends, unless another node still publishes /clock, so a
later rosrun does not wait for a clock that has gone.
"""
import signal

signal.signal(signal.SIGINT, signal.SIG_DFL)  # a signal during the imports: gone, quietly

from rbx1_nav.common.node_ros import exit_node  # noqa: E402
from rbx1_nav.common.params import flag, integer, number, param  # noqa: E402
from rbx1_nav.sim_time.clock_ros import sim_clock  # noqa: E402
from rbx1_nav.sim_time.lockstep_ros import FIRST_MEMBER  # noqa: E402
from rbx1_nav.sim_time.pacer import MAX_SPEED, MAX_START, MAX_STEP, MIN_SPEED, MIN_STEP, speed  # noqa: E402

PARAMS = (
    param('speed', 1.0, speed, 'x real time', 'simulated seconds per wall '
          'second (%g to %g), or max (sim_clock.launch: sim_speed)'
          % (MIN_SPEED, MAX_SPEED)),
    param('idle_speed', 10.0, number, 'x real time', 'with speed max: the '
          'speed while only simulators take part in lockstep',
          minimum=MIN_SPEED, maximum=MAX_SPEED),
    param('step', MAX_STEP, number, 's', 'simulated time per /clock message '
          'when no lockstep member asks for a time', minimum=MIN_STEP,
          maximum=MAX_STEP),
    param('start_time', 0.0, number, 's', 'simulated time at start',
          minimum=0.0, maximum=MAX_START),
    param('members', 1, integer, '', 'under lockstep: members to wait for '
          'before time starts (all of a graph\'s: the same start on every run)',
          minimum=1),
    param('member_wait', FIRST_MEMBER, number, 's', 'wall time to wait for '
          'them before starting without the others', minimum=0.0),
    param('clear_sim_time', False, flag, '', 'at its end under roslaunch, '
          'remove /use_sim_time and /lockstep (its launch set them) unless '
          'another node publishes /clock (sim_clock.launch: true)'),
)

NAME = 'sim_clock'

if __name__ == '__main__':
    exit_node(NAME, sim_clock(PARAMS, __doc__))
