"""Warn when a second node publishes on a robot's cmd_vel (rbx1_nav.publishers).

:func:`watch_publishers` looks at the master's list of publishers at
start and every PERIOD s of wall time, from a daemon thread, over an
XML-RPC connection with a timeout: with the master unreachable it says
nothing new and blocks nothing.
"""
import threading

import rosgraph
import rospy

from rbx1_nav.publishers import NewPublishers, warning_text
from rbx1_nav.ros.master import proxy

PERIOD = 3.0  # wall s between looks at the master


def topic_publishers(master, topics):
    """{topic: [node, ...]} for ``topics`` from ``master``'s system state;
    None when the master cannot tell (unreachable, an error)."""
    try:
        code, _, state = master.getSystemState(rospy.get_name())
    except Exception:  # refused, timed out, a bad reply
        return None
    if code != 1:
        return None
    listed = dict((topic, nodes) for topic, nodes in state[0])
    return {topic: listed.get(topic, []) for topic in topics}


def watch_publishers(name, topics, own=None):
    """Warn, prefixed ``name``, of each new publisher to warn about on
    ``topics`` (resolved names): every other one when this node (``own``,
    its name) publishes there, every one once two or more do when ``own``
    is None (the robot's side)."""
    checks = {topic: NewPublishers(own) for topic in topics}

    def watch():
        master = proxy(rosgraph.get_master_uri())
        while not rospy.core.is_shutdown():
            listed = topic_publishers(master, topics) or {}
            for topic, publishers in sorted(listed.items()):
                new = checks[topic].update(publishers)
                if new:
                    rospy.logwarn('%s: %s', name,
                                  warning_text(topic, new, publishers, own))
            rospy.rostime.wallsleep(PERIOD)

    threading.Thread(target=watch, name='publisher_watch', daemon=True).start()
