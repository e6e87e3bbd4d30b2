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
"""
import time

import rospy

from rbx1_nav.common.params import number, param
from rbx1_nav.common.lockstep_member_ros import enabled as lockstep_enabled
from rbx1_nav.sim_time import lockstep_ros
from rbx1_nav.common.node_ros import start_node
from rbx1_nav.sim_time.pacer import MAX_SPEED, MAX_START, MAX_STEP, MIN_SPEED, MIN_STEP, ClockPacer, speed

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
)


def run_free(pacer):
    """/clock on the pacer's steps, nothing to wait for."""
    clock = lockstep_ros.ClockPublisher()
    while not rospy.is_shutdown():
        sim_ns, wait = pacer.advance(time.monotonic())
        if wait > 0:
            time.sleep(wait)
        if not clock.publish(sim_ns):
            break


def run_lockstep(pacer, speed, idle_speed):
    """Own simulated time: each step goes to /clock, then to the members
    it is granted to, and the next starts once they have handled it."""
    pacer.advance(time.monotonic())  # a first time after 0, which ROS reads as unset
    # At full speed nothing watches the wall clock between two ticks of a
    # motion node: the simulators step through their own grids alone.
    owner = lockstep_ros.TimeOwner(pacer.sim_ns, pacer.step_ns, batch=speed is None)
    # Time starts with its members: the simulators (and the nodes of an
    # earlier sim_clock, started again from further back) join first.
    owner.wait_for_members(lockstep_ros.FIRST_MEMBER)

    def plan(grant, drives):
        target, names = grant if grant else (None, [])
        if speed is None:
            pacer.set_speed(None if drives else idle_speed if grant else 1.0)
        sim_ns, wait = pacer.advance(time.monotonic(), target)
        return sim_ns, names, wait

    owner.run(plan)


def main():
    values = start_node('sim_clock', PARAMS, __doc__, clock=False)
    if values is None:
        raise SystemExit(1)
    speed = values['speed']
    pacer = ClockPacer(speed, values['step'], values['start_time'])
    if not rospy.get_param('/use_sim_time', False):
        rospy.logwarn('sim_clock: /use_sim_time is not set; nodes will ignore /clock')
    if lockstep_enabled():
        run_lockstep(pacer, speed, values['idle_speed'])
        return
    if speed is None:
        rospy.logwarn("sim_clock: ~speed max without /lockstep has nothing to "
                      "wait for: running at real time")
        pacer.set_speed(1.0)
    run_free(pacer)


if __name__ == '__main__':
    main()
