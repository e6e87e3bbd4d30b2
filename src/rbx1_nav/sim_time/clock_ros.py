"""sim_clock's ROS side (nodes/sim_clock.py): /clock at ~speed times real
time on the pacing of rbx1_nav.sim_time.pacer.ClockPacer (:func:`run_free`)
or, with the global parameter /lockstep true, as the one owner of simulated
time (:func:`run_lockstep`, on rbx1_nav.sim_time.lockstep_ros.TimeOwner).
"""
import time

import rospy

from rbx1_nav.common.already_up_ros import running_already
from rbx1_nav.common.launch_end import parent_is_roslaunch
from rbx1_nav.common.launch_end_ros import end_sim_time
from rbx1_nav.common.node_ros import start_node
from rbx1_nav.sim_time import lockstep_ros, switch_ros
from rbx1_nav.sim_time.pacer import ClockPacer

__all__ = ['sim_clock', 'run_free', 'run_lockstep']


def run_free(pacer):
    """/clock on the pacer's steps, nothing to wait for."""
    clock = lockstep_ros.ClockPublisher()
    while not rospy.is_shutdown():
        sim_ns, wait = pacer.advance(time.monotonic())
        if wait > 0:
            time.sleep(wait)
        if not clock.publish(sim_ns):
            break


def run_lockstep(pacer, speed, idle_speed, members=1, member_wait=lockstep_ros.FIRST_MEMBER):
    """Own simulated time: each step goes to /clock, then to the members
    it is granted to, and the next starts once they have handled it."""
    pacer.advance(time.monotonic())  # a first time after 0, which ROS reads as unset
    # At full speed nothing watches the wall clock between two ticks of a
    # motion node: the simulators step through their own grids alone.
    owner = lockstep_ros.TimeOwner(pacer.sim_ns, pacer.step_ns, batch=speed is None)
    # Time starts with its members: the simulators (and the nodes of an
    # earlier sim_clock, started again from further back) join first.
    owner.wait_for_members(member_wait, members)

    def plan(grant, drives):
        target, names = grant if grant else (None, [])
        if speed is None:
            pacer.set_speed(None if drives else idle_speed if grant else 1.0)
        sim_ns, wait = pacer.advance(time.monotonic(), target)
        return sim_ns, names, wait

    owner.run(plan)


def sim_clock(specs, doc):
    """nodes/sim_clock.py: read ``specs`` (``doc`` heads --help), then
    publish /clock, owning simulated time under /lockstep, until shutdown;
    the exit status (1: a bad parameter). With ~clear_sim_time, the clock
    of a roslaunch removes its launch's /use_sim_time and /lockstep as it
    ends (rbx1_nav.common.launch_end.sim_time_to_clear). A clock already
    running under this node's name is left alone: 0, having said so."""
    if running_already('sim_clock'):
        return 0
    values = start_node('sim_clock', specs, doc, clock=False)
    if values is None:
        return 1
    try:
        return _publish(values)
    finally:
        if values['clear_sim_time'] and parent_is_roslaunch():
            end_sim_time(rospy.get_name())


def _publish(values):
    """/clock, as ``values`` say, until shutdown; the exit status."""
    speed = values['speed']
    pacer = ClockPacer(speed, values['step'], values['start_time'])
    if not switch_ros.use_sim_time():
        rospy.logwarn('sim_clock: /use_sim_time is not set; nodes will ignore /clock')
    if switch_ros.lockstep():
        run_lockstep(pacer, speed, values['idle_speed'], values['members'],
                     values['member_wait'])
        return 0
    if speed is None:
        rospy.logwarn("sim_clock: ~speed max without /lockstep has nothing to "
                      "wait for: running at real time")
        pacer.set_speed(1.0)
    run_free(pacer)
    return 0

