"""Warn when a second node publishes on a robot's cmd_vel (rbx1_nav.common.cmd_vel_watch).

:func:`watch_publishers` looks at the master's list of publishers at
start and every PERIOD s of wall time, from a daemon thread, over an
XML-RPC connection with a timeout: with the master unreachable it says
nothing new and blocks nothing.
"""
import threading

import rospy

from rbx1_nav.common.cmd_vel_watch import NewPublishers, warning_text
from rbx1_nav.common.master_ros import topic_graph

PERIOD = 3.0  # wall s between looks at the master


def watch_publishers(name, topics, own=None):
    """Warn, prefixed ``name``, of each new publisher to warn about on
    ``topics`` (resolved names): every other one when this node (``own``,
    its name) publishes there, every one once two or more do when ``own``
    is None (the robot's side)."""
    checks = {topic: NewPublishers(own) for topic in topics}

    def watch():
        while not rospy.core.is_shutdown():
            graph = topic_graph()
            for topic in sorted(topics) if graph else ():
                publishers = graph[0].get(topic, [])
                new = checks[topic].update(publishers)
                if new:
                    rospy.logwarn('%s: %s', name,
                                  warning_text(topic, new, publishers, own))
            rospy.rostime.wallsleep(PERIOD)

    threading.Thread(target=watch, name='publisher_watch', daemon=True).start()
