"""Re-registering with a restarted master, for the nodes that do (the filters): rospy
registers once, so new nodes could not find this one's topics (common.master_watch)."""
import rosgraph
import rospy

from rbx1_nav.common.master_ros import PERIOD, TIMEOUT, problem_text, proxy, reply_value
from rbx1_nav.common.master_watch import reregistering_text
from rbx1_nav.common.rospy_private_ros import registrations

__all__ = ['reregister', 'reregister_node']

ATTEMPTS = 3  # re-registrations tried after a restart, PERIOD apart


def reregister(timeout=TIMEOUT):
    """Register this process's topics and services (rospy's own, so their
    connections go on) with the master, as rospy does at start-up; returns
    how many of each, raises if the master does not answer."""
    uri, node_uri = rosgraph.get_master_uri(), rospy.get_node_uri()
    caller_id = rospy.get_caller_id()
    # A registration stuck on an unreachable master holds rospy's lock.
    registered = registrations(timeout)
    if registered is None:
        raise RuntimeError('rospy is busy registering a topic')
    publications, subscriptions, services = registered
    with proxy(uri, timeout) as master, proxy(node_uri, timeout) as node:
        for topic, msg_type in publications:
            reply_value(master.registerPublisher(caller_id, topic, msg_type, node_uri),
                        'registerPublisher ' + topic)
        for topic, msg_type in subscriptions:
            publishers = reply_value(master.registerSubscriber(
                caller_id, topic, msg_type, node_uri), 'registerSubscriber ' + topic)
            if publishers:  # as the master would: our own slave API
                node.publisherUpdate('/master', topic, publishers)
        for service, service_uri in services:
            reply_value(master.registerService(caller_id, service, service_uri, node_uri),
                        'registerService ' + service)
    return len(publications) + len(subscriptions), len(services)


def reregister_node(name, uri, attempts=ATTEMPTS, pause=PERIOD):
    """An ``on_restarted`` that re-registers, ``attempts`` times ``pause`` s apart."""
    rospy.logwarn(reregistering_text(name, uri))
    problem = None
    for attempt in range(attempts):
        try:
            topics, services = reregister()
        except Exception as err:
            problem = problem_text(err)
            if attempt + 1 < attempts:
                rospy.rostime.wallsleep(pause)
            continue
        rospy.loginfo('%s: re-registered %d topics and %d services with the '
                      'new master at %s', name, topics, services, uri)
        return True
    rospy.logwarn('%s: could not re-register with the master at %s (%s): new nodes cannot find '
                  'this node\'s topics. Fix: restart this node', name, uri, problem)
    return False
