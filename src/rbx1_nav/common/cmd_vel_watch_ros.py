"""Warn of a second node on a robot's cmd_vel, from a thread: it blocks nothing."""
import threading

import rospy

from rbx1_nav.common.cmd_vel_watch import NewPublishers, warning_text
from rbx1_nav.common.master_ros import topic_graph

PERIOD = 3.0  # wall s between looks at the master


def watch_publishers(name, topics, own=None):
    """Warn of new publishers on ``topics`` (resolved), as NewPublishers(``own``)."""
    checks = {topic: NewPublishers(own) for topic in topics}

    def watch():
        while not rospy.core.is_shutdown():
            graph = topic_graph()
            for topic in sorted(topics) if graph else ():
                publishers = graph[0].get(topic, [])
                new = checks[topic].update(publishers)
                if new:
                    rospy.logwarn('%s: %s', name, warning_text(topic, new, publishers, own))
            rospy.rostime.wallsleep(PERIOD)

    threading.Thread(target=watch, name='publisher_watch', daemon=True).start()
