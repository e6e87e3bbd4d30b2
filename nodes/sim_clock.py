#!/usr/bin/env python3
"""sim_clock: publish /clock at ~speed times real time, for /use_sim_time runs.

One clock serves every robot on the master, so it publishes the global
/clock topic. This is the only node that reads the wall clock; every other
node follows the simulated time it publishes, so tests run the same at 1x
and at 20x. The pacing itself is rbx1_nav.sim_clock.ClockPacer.

With the global parameter /lockstep true (sim_clock.launch lockstep:=true),
time also waits for the simulators that report on /clock_lockstep, and
they wait for their motion nodes (rbx1_nav.lockstep): a course then ends
the same at any speed and under any load. ~speed max runs as fast as they
allow; with no simulator taking part yet, 'max' runs at real time.

Parameters: ~speed (1.0, x real time, 0.001 to 1e6, or max), ~step (0.01 s
of sim time per tick, 1e-9 to 0.01), ~start_time (0.0 s, at most 2**31).
"""
import time

import rospy
from rosgraph_msgs.msg import Clock

from rbx1_nav.params import number, param
from rbx1_nav.ros import lockstep
from rbx1_nav.ros.node import start_node
from rbx1_nav.sim_clock import MAX_START, MAX_STEP, MIN_STEP, ClockPacer, speed

PARAMS = (
    param('speed', 1.0, speed, 'x real time', 'simulated seconds per wall '
          "second, or max (sim_clock.launch: sim_speed)"),
    param('step', MAX_STEP, number, 's', 'simulated time per /clock message',
          minimum=MIN_STEP, maximum=MAX_STEP),
    param('start_time', 0.0, number, 's', 'simulated time at start',
          minimum=0.0, maximum=MAX_START),
)


def main():
    values = start_node('sim_clock', PARAMS, __doc__, clock=False)
    if values is None:
        raise SystemExit(1)
    speed = values['speed']
    pacer = ClockPacer(speed, values['step'], values['start_time'])
    if not rospy.get_param('/use_sim_time', False):
        rospy.logwarn('sim_clock: /use_sim_time is not set; nodes will ignore /clock')
    keeper = lockstep.Keeper('sim_clock', lockstep.CLOCK_TOPIC) if lockstep.enabled() else None
    if keeper is None and speed is None:
        rospy.logwarn("sim_clock: ~speed max without /lockstep has nothing to "
                      "wait for: running at real time")
        pacer.set_speed(1.0)
    pub = lockstep.synchronous_publisher('/clock', Clock)
    while not rospy.is_shutdown():
        limit = None
        if keeper is not None:
            # Every simulator has handled the time now published; the next
            # one is a step on, or the earliest tick one of them asked for.
            if not keeper.wait_allows(pacer.sim_ns + 1):
                break
            limit = keeper.next_tick()
            if speed is None:
                pacer.set_speed(None if keeper.has_members() else 1.0)
        sim_ns, wait = pacer.advance(time.monotonic(), limit)
        if wait > 0:
            time.sleep(wait)
        try:
            pub.publish(Clock(clock=lockstep.from_ns(sim_ns)))
        except rospy.ROSException:
            # Publishing fails only while shutting down, which a signal
            # starts in another thread (rbx1_nav.ros.node).
            if not rospy.core.is_shutdown_requested():
                raise
            break


if __name__ == '__main__':
    main()
