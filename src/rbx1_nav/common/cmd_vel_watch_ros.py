"""Warn of a second node on a robot's cmd_vel, from a thread: it blocks nothing. What each one is
(rbx1_nav.common.cmd_vel_watch.kind_of) comes from the master and, for a course, from the header
of this process's own connection to it."""
import threading

import rospy

from rbx1_nav.common.cmd_vel_watch import (COURSE, MUX_INPUT, UNKNOWN, NewPublishers, is_course,
                                           kind_of, mux_input, warning_text)
from rbx1_nav.common.master_ros import topic_graph
from rbx1_nav.common.rospy_private_ros import (publisher_name, subscribed_connections,
                                              transport_header)

PERIOD = 3.0  # wall s between looks at the master


def heard_headers(topic):
    """{publisher node: its connection header} of this process's subscription to ``topic``
    (resolved), for the connections whose header has come; None if it does not subscribe."""
    found = subscribed_connections(topic)
    if found is None:
        return None
    headers = ((publisher_name(c), transport_header(c)) for c in found)
    return {node: header for node, header in headers if header is not None}


def kinds(graph, topic, nodes):
    """node -> (kind, its multiplexer input) for ``nodes`` publishing on ``topic``, from the
    master's ``graph`` (topic_graph()); None for a node that subscribes to the topic as a course
    does, when this process hears the topic but its connection to the node is not up yet."""
    _, subscribers, types = graph
    takers = subscribers.get(topic, ())
    headers = heard_headers(topic)
    courses = _courses(headers)
    found = {}
    for node in nodes:
        if node in takers and headers is not None and node not in headers:
            found[node] = None  # a course or a multiplexer: ask again when connected
            continue
        kind = kind_of(node, takers, courses)
        found[node] = (kind, mux_input(node, subscribers, types, topic))
    return found


def kind_now(topic, node):
    """(kind, multiplexer input) of ``node`` on ``topic`` now: UNKNOWN when the master does not
    answer, unless the node's header says it is a course."""
    graph = topic_graph()
    if graph is None:
        return (COURSE if node in courses_heard(topic) else UNKNOWN), MUX_INPUT
    return kinds(graph, topic, [node])[node] or (UNKNOWN, MUX_INPUT)


def _courses(headers):
    """The nodes among ``headers`` (heard_headers()) whose header says they are courses."""
    return {node for node, header in (headers or {}).items() if is_course(header)}


def courses_heard(topic):
    """The nodes whose course header this process's subscription to ``topic`` has read."""
    return _courses(heard_headers(topic))


def watch_publishers(name, topics, own=None, now=True, also=None):
    """Warn of new publishers on ``topics`` (resolved), as NewPublishers(``own``), every PERIOD s
    from a thread, and first at once unless ``now`` is false; returns a look to call any time
    (a course calls it once it hears the others, before it drives, with the master's graph it
    already has), and ``also(graph)`` at each look the master answered."""
    checks = {topic: NewPublishers(own) for topic in topics}
    lock = threading.Lock()

    def look(graph=None):
        graph = graph or topic_graph()
        with lock:
            if also and graph:
                also(graph)
            for topic in sorted(topics) if graph else ():
                publishers = graph[0].get(topic, [])
                found = kinds(graph, topic, set(publishers) - {own})
                settled = [node for node in publishers if found.get(node, ()) is not None]
                new = checks[topic].update(settled)
                if new:
                    rospy.logwarn('%s: %s', name, warning_text(
                        topic, new, settled, own, {node: found[node] for node in new}))

    def watch():
        while not rospy.core.is_shutdown():
            rospy.rostime.wallsleep(PERIOD)
            look()

    if now:
        look()
    threading.Thread(target=watch, name='publisher_watch', daemon=True).start()
    return look

