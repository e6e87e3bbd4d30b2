"""Tell from repeated polls whether the ROS master went away, came back, or
was replaced by a new one.

ROS 1 nodes register their topics with the master once, at start-up; rospy
never registers them again. Topic connections are peer to peer and outlive
the master, so a node whose master restarted goes on working over the
connections it has, while the new master knows nothing of it: RViz and
other new nodes cannot find its topics, and it cannot find theirs. Nothing
in rospy says so. :class:`MasterStates` turns one observation per poll (the
master's identity, or None when it did not answer) into the events a node
acts on. It imports no rospy; ``rbx1_nav.common.master_ros`` does the polling.
"""
import re
import xmlrpc.client

#: Failed polls in a row before the master counts as gone, so that a lossy
#: link (one poll in three lost) does not make the warning come and go.
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
    """An XML-RPC proxy to ``uri`` (the master, a node) whose calls time out
    after ``timeout`` s: never rospy's connection, which has no timeout."""
    return xmlrpc.client.ServerProxy(uri, transport=_TimeoutTransport(timeout))


#: rosmaster's shutdown request to a node that a new node of its name
#: replaces (rosmaster.registrations.shutdown_node_task).
_REPLACED = re.compile(r'\[([^\]]*)\] Reason: new node registered with same name')


def replaced_node(msg):
    """The node name in a master's shutdown request ``msg`` saying that a
    new node of that name replaced it; None for any other request (a user's
    ``rosnode kill``)."""
    found = _REPLACED.match(msg or '')
    return found.group(1) if found else None


def misdirected_text(name, meant):
    """A node refusing the master's shutdown meant for the node ``meant``."""
    return ('%s: the ROS master asked this node to shut down because a new '
            '%s replaced the old one, whose address it still had: that node '
            'ended without unregistering and this one got its port '
            '(ros/ros_comm#2241); refused, this node goes on' % (name, meant))


def same_master(seen, reference):
    """Whether identity ``seen`` can be the master ``reference``.

    An identity is (pid, run_id). The pid alone could repeat (a master
    restarted in a container often gets the same one); roscore's
    ``/run_id`` is new on every start but is set a moment after the master
    answers, and a bare rosmaster has none: None, which matches any.
    """
    (pid, run_id), (reference_pid, reference_run_id) = seen, reference
    if pid != reference_pid:
        return False
    return None in (run_id, reference_run_id) or run_id == reference_run_id


class MasterStates(object):
    """Feed :meth:`observe` one identity per poll; it returns an event.

    An identity is (pid, run_id) (see same_master); None means the poll
    failed. The first identity seen is taken for the master the node
    registered with, so start watching right after start-up. A node that
    starts watching while the master is unreachable cannot tell a restart
    from a return; the first master it sees is the reference (BACK if GONE
    was reported before it).
    """

    def __init__(self, gone_after=GONE_AFTER):
        if gone_after < 1:
            raise ValueError('gone_after must be at least 1, not %r' % gone_after)
        self.gone_after = gone_after
        self.identity = None  # the master this node is registered with
        self.failures = 0  # failed polls in a row
        self.gone = False  # 'gone' was reported and nothing since

    def observe(self, identity):
        """One poll's result -> None, GONE, BACK or RESTARTED.

        GONE once ``gone_after`` polls in a row failed (and not again until
        the master answered); BACK when the same master answers again after
        GONE; RESTARTED when a different master answers, whether or not
        GONE came first (a restart can be quicker than ``gone_after``
        polls). After RESTARTED the new master is the reference.
        """
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
    """What a restarted master means to a node that does not re-register,
    and what to do about it."""
    return ('%s: the ROS master at %s restarted: this node\'s topics were '
            'registered with the old one; its existing connections go on, but '
            'new nodes (RViz, rostopic) cannot find its topics and it cannot '
            'find new publishers. Fix: restart this node (pose_ekf and '
            'odom_ekf re-register by themselves)' % (name, uri))


def reregistering_text(name, uri):
    """What a node that re-registers says when the master restarted."""
    return ('%s: the ROS master at %s restarted: re-registering this node\'s '
            'topics and services with it, so that new nodes (RViz, rostopic) '
            'find them again; connections made before go on. Its parameters '
            'went with the old master (this node keeps the values it read at '
            'start-up). Nodes that do not re-register (most drivers) are '
            'unknown to the new master until they are restarted'
            % (name, uri))


def gone_text(name, uri, problem):
    """The master stopped answering: what still works and what does not."""
    return ('%s: the ROS master at %s is unreachable (%s): connections made '
            'before go on, but no node or topic can join until it is back'
            % (name, uri, problem))
