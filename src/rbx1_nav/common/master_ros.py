"""Watch the ROS master from a thread of its own (why: common.master_watch; re-registering
with a new one: common.reregister_ros). Each call is its own XML-RPC connection with a
timeout, never rospy's, which has none: an unreachable master stalls the watch, not the node."""
import threading

import rosgraph
import rospy

from rbx1_nav.common.master_watch import BACK, GONE, RESTARTED, TIMEOUT, MasterStates, proxy

__all__ = ['MasterWatch', 'proxy', 'topic_graph', 'node_answers', 'master_identity', 'reply_value',
           'problem_text']

PERIOD = 1.0  # s between polls


def reply_value(reply, what):
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
            state = reply_value(master.getSystemState(caller_id), 'getSystemState')
            types = reply_value(master.getTopicTypes(caller_id), 'getTopicTypes')
    except Exception:  # refused, timed out, reset, bad reply
        return None
    return dict(state[0]), dict(state[1]), dict(types)


def node_answers(name, timeout=TIMEOUT):
    """Whether ``name`` answers where the master has it (a killed node stays registered)."""
    caller_id = rospy.get_caller_id()
    try:
        with proxy(rosgraph.get_master_uri(), timeout) as master:
            uri = reply_value(master.lookupNode(caller_id, name), 'lookupNode')
        with proxy(uri, timeout) as node:
            reply_value(node.getPid(caller_id), 'getPid')
    except Exception:  # not registered, refused, timed out, bad reply
        return False
    return True


def master_identity(uri, caller_id, timeout=TIMEOUT):
    """(pid, run_id or None) of the master at ``uri``; raises if it does not answer."""
    with proxy(uri, timeout) as master:
        pid = reply_value(master.getPid(caller_id), 'getPid')
        code, _, run_id = master.getParam(caller_id, '/run_id')
    return pid, (run_id if code == 1 else None)


def problem_text(err):
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
            identity, problem = None, problem_text(err)
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
