"""The ROS side of lockstep_play.py: a bag's messages published as a
lockstep member (what it publishes when: rbx1_nav.sim.bag_play).

Each played topic is published under its relative name (``/encoder`` on
``encoder``), so a ``<group ns>`` or a remap applies to it, through a
counted publisher: a filter granted a step waits for every message the
player reported and reads exactly those.
"""
import time

import rosbag
import roslib.message
import rospy

from rbx1_nav.sim_time import member_ros as lockstep
from rbx1_nav.sim_time import switch_ros
from rbx1_nav.sim_time.member import BACK
from rbx1_nav.common.node_ros import forget_command_line, start_node
from rbx1_nav.sim.bag_play import Schedule

#: Progress lines: one every tenth of the bag.
PROGRESS_STEPS = 10


def _publishers(member, bag, wanted, name):
    """{bag topic: counted publisher} for ``wanted`` (empty: every topic);
    a topic the bag lacks is skipped with a warning. ValueError when none
    is left, or a type is not installed."""
    info = bag.get_type_and_topic_info().topics
    wanted = ['/' + t.lstrip('/') for t in wanted]
    topics = [t for t in wanted if t in info] if wanted else sorted(info)
    missing = sorted(set(wanted) - set(topics))
    if missing:
        rospy.logwarn('%s: %s has no %s: not played (it has: %s)', name,
                      bag.filename, ', '.join(missing), ', '.join(sorted(info)))
    if not topics:
        raise ValueError('none of its topics to play')
    pubs = {}
    for topic in topics:
        msg_class = roslib.message.get_message_class(info[topic].msg_type)
        if msg_class is None:
            raise ValueError('message type %s of %s is not installed' % (
                info[topic].msg_type, topic))
        pubs[topic] = member.publisher(rospy.resolve_name(topic.lstrip('/')),
                                       msg_class)
    return pubs


def _wait_for_subscribers(pubs, count, wait, name):
    """Wait up to ``wait`` wall s until each topic has ``count`` subscribers."""
    deadline = time.monotonic() + wait
    while not rospy.is_shutdown():
        short = sorted(p.resolved_name for p in pubs.values()
                       if p.get_num_connections() < count)
        if not short:
            return
        if time.monotonic() > deadline:
            rospy.logwarn('%s: fewer than %d subscriber(s) on %s after %.0f s; '
                          'playing anyway', name, count, ', '.join(short), wait)
            return
        rospy.rostime.wallsleep(0.05)


def main(name, specs, doc):
    """main() of lockstep_play.py; returns the exit status (1: a bad
    parameter or bag, no lockstep, time moved back)."""
    values = start_node(name, specs, doc)
    if values is None:
        return 1
    if not switch_ros.lockstep():
        rospy.logfatal('%s: /use_sim_time and /lockstep are not both true: this '
                       'player needs lockstep simulated time (roslaunch rbx1_nav '
                       'sim_clock.launch sim_speed:=max); for real time use '
                       'rosbag play', name)
        forget_command_line()
        return 1
    member = lockstep.Member()
    try:
        bag = rosbag.Bag(values['bag'])
        pubs = _publishers(member, bag, values['topics'], name)
    except (OSError, ValueError, rosbag.ROSBagException) as err:
        rospy.logfatal('%s: cannot play %s: %s', name, values['bag'], err)
        forget_command_line()
        return 1
    rospy.on_shutdown(member.leave)
    _wait_for_subscribers(pubs, values['subscribers'], values['subscriber_wait'], name)
    schedule = Schedule(((t.to_nsec(), topic, msg) for topic, msg, t in
                         bag.read_messages(topics=sorted(pubs))), values['start'])
    if schedule.next_time is None:
        rospy.logwarn('%s: nothing to play in %s from %.1f s on', name,
                      values['bag'], values['start'])
        return 0
    begin, end = schedule.next_time, int(bag.get_end_time() * 1e9)
    length = max(1, end - begin)
    rospy.loginfo('%s: playing %s (%s), %.1f s of it, in lockstep', name,
                  values['bag'], ', '.join(sorted(pubs)), length * 1e-9)
    if not member.join_patiently(name):
        return 0
    shown = 0
    for action, tick, _ in member.grants(name):
        if action == BACK:
            rospy.logerr('%s: simulated time moved back (sim_clock restarted); '
                         'stopping the replay', name)
            return 1
        for topic, msg in schedule.due(tick):
            pubs[topic].publish(msg)
        if schedule.next_time is None:
            member.leave()
            rospy.loginfo('%s: played %d messages, to the end of the bag',
                          name, schedule.played)
            return 0
        part = PROGRESS_STEPS * (tick - begin) // length
        if part > shown:
            shown = part
            rospy.loginfo('%s: %d %% (%.1f of %.1f s)', name, 100 * part // PROGRESS_STEPS,
                          (tick - begin) * 1e-9, length * 1e-9)
        member.report(tick, max(schedule.next_time, tick + 1))
    return 0

