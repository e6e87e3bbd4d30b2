"""Whether the ROS master went away, came back or was replaced (master_ros polls).
rospy registers topics once: after a master restart new nodes (RViz) cannot find a node's
topics, nor it theirs, and nothing says so. No rospy here."""
import re
import xmlrpc.client

#: Failed polls in a row before the master counts as gone: a lossy link must not toggle a warning.
GONE_AFTER = 3

GONE, BACK, RESTARTED = 'gone', 'back', 'restarted'

TIMEOUT = 2.0  # s, socket timeout of each call to the master (or a node)


class _TimeoutTransport(xmlrpc.client.Transport):
    """An XML-RPC transport whose connections time out after ``timeout`` s."""

    def __init__(self, timeout):
        super(_TimeoutTransport, self).__init__()
        self.timeout = timeout

    def make_connection(self, host):
        connection = super(_TimeoutTransport, self).make_connection(host)
        connection.timeout = self.timeout  # used by connect(), for every call
        return connection


def proxy(uri, timeout=TIMEOUT):
    """An XML-RPC proxy to ``uri`` whose calls time out after ``timeout`` s, unlike rospy's."""
    return xmlrpc.client.ServerProxy(uri, transport=_TimeoutTransport(timeout))


#: rosmaster's shutdown to a replaced node (registrations.shutdown_node_task).
_REPLACED = re.compile(r'\[([^\]]*)\] Reason: new node registered with same name')


def replaced_node(msg):
    """The node a shutdown request ``msg`` says a new one replaced; None if another request."""
    found = _REPLACED.match(msg or '')
    return found.group(1) if found else None


def misdirected_text(name, meant):
    """A node refusing the master's shutdown meant for the node ``meant``."""
    return ('%s: the ROS master asked this node to shut down because a new %s replaced the old '
            'one, whose address it still had: that node ended without unregistering and this one '
            'got its port (ros/ros_comm#2241); refused, this node goes on' % (name, meant))


def same_master(seen, reference):
    """Whether identity (pid, run_id) ``seen`` can be the master ``reference``: a
    pid can repeat (in a container); roscore's ``/run_id`` cannot, but may be
    None (set late, or a bare rosmaster), which matches any."""
    (pid, run_id), (ref_pid, ref_run_id) = seen, reference
    return pid == ref_pid and (None in (run_id, ref_run_id) or run_id == ref_run_id)


class MasterStates(object):
    """Events from one identity per poll (None: failed); the first one seen is
    taken for the node's master, so start watching right after start-up."""

    def __init__(self, gone_after=GONE_AFTER):
        if gone_after < 1:
            raise ValueError('gone_after must be at least 1, not %r' % gone_after)
        self.gone_after = gone_after
        self.identity = None  # the master this node is registered with
        self.failures = 0  # failed polls in a row
        self.gone = False  # 'gone' was reported and nothing since

    def observe(self, identity):
        """One poll's result -> None, GONE (once, after ``gone_after``
        failures in a row), BACK (the same master after GONE) or RESTARTED
        (a different one, GONE or not; it becomes the reference)."""
        if identity is None:
            self.failures += 1
            if self.failures >= self.gone_after and not self.gone:
                self.gone = True
                return GONE
            return None
        was_gone, self.failures, self.gone = self.gone, 0, False
        reference, self.identity = self.identity, tuple(identity)
        if reference is not None:
            if not same_master(identity, reference):
                return RESTARTED
            if identity[1] is None:  # keep the run_id seen before
                self.identity = (identity[0], reference[1])
        return BACK if was_gone else None


def restarted_text(name, uri):
    """A restarted master, to a node that does not re-register."""
    return ('%s: the ROS master at %s restarted: this node\'s topics were registered with the old '
            'one; its existing connections go on, but new nodes (RViz, rostopic) cannot find its '
            'topics and it cannot find new publishers. Fix: restart this node (pose_ekf and '
            'odom_ekf re-register by themselves)' % (name, uri))


def reregistering_text(name, uri):
    """What a node that re-registers says when the master restarted."""
    return ('%s: the ROS master at %s restarted: re-registering this node\'s topics and services '
            'with it, so that new nodes (RViz, rostopic) find them again; connections made before '
            'go on. Its parameters went with the old master (this node keeps the values it read at '
            'start-up). Nodes that do not re-register (most drivers) are unknown to the new master '
            'until they are restarted' % (name, uri))


def gone_text(name, uri, problem):
    """The master stopped answering: what still works and what does not."""
    return ('%s: the ROS master at %s is unreachable (%s): connections made before go on, but no '
            'node or topic can join until it is back' % (name, uri, problem))
