"""Watch the ROS master from a thread of its own; re-register with a new one (why:
common.master_watch). Each call is its own XML-RPC connection with a timeout, never rospy's,
which has none: an unreachable master stalls the watch, never the node."""
import threading

import rosgraph
import rospy

from rbx1_nav.common.master_watch import (BACK, GONE, RESTARTED, TIMEOUT,
                                          MasterStates, proxy, reregistering_text)
from rbx1_nav.common.rospy_private_ros import registrations

__all__ = ['MasterWatch', 'proxy', 'topic_graph', 'node_answers', 'reregister', 'reregister_node']

PERIOD = 1.0  # s between polls
ATTEMPTS = 3  # re-registrations tried after a restart, PERIOD apart


def _value(reply, what):
    """The value of a ROS XML-RPC reply [code, message, value]."""
    code, message, value = reply
    if code != 1:
        raise RuntimeError('%s: %s' % (what, message))
    return value


def topic_graph(timeout=TIMEOUT):
    """The master's (publishers, subscribers, types) by topic; None if it does not answer."""
    caller_id = rospy.get_caller_id()
    try:
        with proxy(rosgraph.get_master_uri(), timeout) as master:
            state = _value(master.getSystemState(caller_id), 'getSystemState')
            types = _value(master.getTopicTypes(caller_id), 'getTopicTypes')
    except Exception:  # refused, timed out, reset, bad reply
        return None
    return dict(state[0]), dict(state[1]), dict(types)


def node_answers(name, timeout=TIMEOUT):
    """Whether ``name`` answers where the master has it (a killed node stays registered)."""
    caller_id = rospy.get_caller_id()
    try:
        with proxy(rosgraph.get_master_uri(), timeout) as master:
            uri = _value(master.lookupNode(caller_id, name), 'lookupNode')
        with proxy(uri, timeout) as node:
            _value(node.getPid(caller_id), 'getPid')
    except Exception:  # not registered, refused, timed out, bad reply
        return False
    return True


def master_identity(uri, caller_id, timeout=TIMEOUT):
    """(pid, run_id or None) of the master at ``uri``; raises if it does not answer."""
    with proxy(uri, timeout) as master:
        pid = _value(master.getPid(caller_id), 'getPid')
        code, _, run_id = master.getParam(caller_id, '/run_id')
    return pid, (run_id if code == 1 else None)


def _problem(err):
    """A short reason a call to the master failed."""
    return getattr(err, 'strerror', None) or str(err) or type(err).__name__


class MasterWatch(object):
    """Polls the master every ``period`` s and calls, in its thread, ``on_gone(uri,
    problem)``, ``on_back(uri)`` or ``on_restarted(uri)`` (MasterStates)."""

    def __init__(self, name, on_gone=None, on_back=None, on_restarted=None,
                 period=PERIOD, timeout=TIMEOUT):
        self.name = name
        self.callbacks = {GONE: on_gone, BACK: on_back, RESTARTED: on_restarted}
        self.period, self.timeout = period, timeout
        self.uri = rosgraph.get_master_uri()
        self.states = MasterStates()
        self._stop, self._thread = threading.Event(), None

    def start(self):
        """Start polling (once): right after init_node, to see the node's own master first."""
        if self._thread is None:
            self._thread = threading.Thread(target=self._run, daemon=True, name='master_watch')
            self._thread.start()
        return self

    def stop(self):
        """Stop polling after the current poll."""
        self._stop.set()

    def poll(self):
        """One poll: returns the event (and calls its callback)."""
        try:
            identity, problem = master_identity(
                self.uri, rospy.get_caller_id(), self.timeout), None
        except Exception as err:  # refused, timed out, reset, bad reply
            identity, problem = None, _problem(err)
        event = self.states.observe(identity)
        callback = self.callbacks.get(event)
        if callback is not None:
            args = (self.uri, problem) if event == GONE else (self.uri,)
            try:
                callback(*args)
            except Exception as err:  # keep watching
                rospy.logerr('%s: handling the master %s failed: %s', self.name, event, err)
        return event

    def _run(self):
        # Event.wait: wall time, which a paused simulated clock does not stop.
        while not rospy.is_shutdown():
            self.poll()
            if self._stop.wait(self.period):
                break


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
            _value(master.registerPublisher(caller_id, topic, msg_type, node_uri),
                   'registerPublisher ' + topic)
        for topic, msg_type in subscriptions:
            publishers = _value(master.registerSubscriber(
                caller_id, topic, msg_type, node_uri), 'registerSubscriber ' + topic)
            if publishers:  # as the master would: our own slave API
                node.publisherUpdate('/master', topic, publishers)
        for service, service_uri in services:
            _value(master.registerService(caller_id, service, service_uri,
                                          node_uri), 'registerService ' + service)
    return len(publications) + len(subscriptions), len(services)


def reregister_node(name, uri, attempts=ATTEMPTS, pause=PERIOD):
    """An ``on_restarted`` that re-registers, ``attempts`` times ``pause`` s apart."""
    rospy.logwarn(reregistering_text(name, uri))
    problem = None
    for attempt in range(attempts):
        try:
            topics, services = reregister()
        except Exception as err:
            problem = _problem(err)
            if attempt + 1 < attempts:
                rospy.rostime.wallsleep(pause)
            continue
        rospy.loginfo('%s: re-registered %d topics and %d services with the '
                      'new master at %s', name, topics, services, uri)
        return True
    rospy.logwarn('%s: could not re-register with the master at %s (%s): new nodes cannot find '
                  'this node\'s topics. Fix: restart this node', name, uri, problem)
    return False
