#!/usr/bin/env python3
"""lockstep_play: play a bag as a lockstep member, at full speed and the
same on every run.

`rosbag play` publishes on the wall clock: on a busy machine some messages
come late, and a filter fed from the bag (pose_ekf.py) answers differently
from run to run. Under lockstep simulated time (sim_clock.launch
sim_speed:=max) this player is granted the time of each message instead:
it publishes every message recorded up to that time, counted, and a
filter that is a member too reads exactly those, so a replay gives the
same estimates to the last digit however busy the machine, as fast as it
allows. Each topic is published under its relative name (/encoder on
encoder), so <group ns> and remaps apply. It exits 0 at the end of the
bag (make it required="true" for the launch to end with it), 1 on a bad
bag or parameter, or without lockstep. For real time, use rosbag play.

    roslaunch rbx1_nav pose_ekf_replay.launch bag:=/path/to.bag fast:=true

Publishes:  each played topic under its relative name, /lockstep_report
Subscribes: /lockstep_grant
"""
import signal

signal.signal(signal.SIGINT, signal.SIG_DFL)  # a signal during the imports: gone, quietly

from rbx1_nav.common.node_ros import exit_node  # noqa: E402
from rbx1_nav.common.params import integer, number, param, text  # noqa: E402
from rbx1_nav.common.params_lists import texts  # noqa: E402
from rbx1_nav.sim.bag_play_ros import main  # noqa: E402

PARAMS = (
    param('bag', '', text, '', 'the bag file to play'),
    param('topics', [], texts, '',
          'topics to play (a list, or names separated by spaces); empty: all'),
    param('start', 0.0, number, 's', 'play from this long after the '
          "bag's first message", minimum=0.0),
    param('subscribers', 1, integer, '', 'start once each topic has this '
          'many subscribers', minimum=0),
    param('subscriber_wait', 30.0, number, 's', 'wall time to wait for '
          'them before playing anyway', minimum=0.0),
)

NAME = 'lockstep_play'

if __name__ == '__main__':
    exit_node(NAME, main(NAME, PARAMS, __doc__))
