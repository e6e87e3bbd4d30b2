"""A lockstep member's way in: waiting for its connections and for the
owner, then the first report (a part of
rbx1_nav.sim_time.member_ros.Member).
"""
import time

import rospy

from rbx1_nav.common.master_ros import node_answers, topic_graph
from rbx1_nav.common.rospy_private_ros import published_connections, subscriber_name
from rbx1_nav.sim_time.member_grants_ros import GRANT_TOPIC, NO_OWNER_WARNING, NoOwnerWarning
from rbx1_nav.sim_time.member_inputs_ros import connected_publishers

#: Wall seconds a member about to join waits for a first grant, once the
#: owner is connected, to learn who the members are (grants go out every
#: step while there are any).
FIRST_GRANT = 1.0


def owners_alive():
    """The nodes registered as publishing grants that answer (a killed one
    stays registered)."""
    graph = topic_graph()
    publishers = graph[0].get(GRANT_TOPIC, ()) if graph else ()
    return [name for name in sorted(publishers) if node_answers(name)]


class JoinError(Exception):
    """A node could not join the lockstep; the message says why."""


class Joining(object):
    """How a member (``name``) joins: its ``reports`` (a Reports) to the
    owner, its ``receiver`` (a GrantReceiver) of the grants, its
    ``inputs`` (a CountedInputs) whose connections it waits for."""

    def __init__(self, name, reports, receiver, inputs):
        self.name = name
        self.reports = reports
        self.receiver = receiver
        self.inputs = inputs

    def connected(self):
        """True once the owner takes this node's reports and sends it grants."""
        return bool(self.reports.pub.get_num_connections()
                    and self.receiver.sub.get_num_connections())

    def join(self, wait):
        """Join the owner's lockstep, waiting for it up to ``wait`` wall
        seconds, and after that as long as a node that grants steps is
        registered and answers (a loaded machine can take longer than
        ``wait`` to start it and connect); the first grant follows. Raises
        JoinError."""
        started = time.monotonic()
        deadline = started + wait
        while not self.connected():  # a report sent before would be lost
            if rospy.is_shutdown():
                raise JoinError('shutting down')
            now = time.monotonic()
            if now > deadline:
                owners = owners_alive()
                if not owners:
                    raise JoinError('nothing grants lockstep steps on %s after %.1f s (is '
                                    'sim_clock running? sim_clock.launch starts it)'
                                    % (GRANT_TOPIC, wait))
                rospy.loginfo('%s: %s is up but not yet connected after %.0f s; waiting '
                              'while it runs', self.name, ', '.join(owners), now - started)
                deadline = now + NO_OWNER_WARNING
            rospy.rostime.wallsleep(0.01)
        self.receiver.restart()
        if self.reports.every_step:
            self.receiver.take_own_time()
        self.reports.start()

    def join_patiently(self, log_name):
        """Join, however long the owner takes to come (a simulator, a
        filter, a bag player: no robot waits on them), warning every
        NO_OWNER_WARNING s, then every NO_OWNER_REMINDER s; False at
        shutdown."""
        warning = NoOwnerWarning(log_name)
        while not rospy.is_shutdown():
            try:
                self.join(NO_OWNER_WARNING)
                return True
            except JoinError:
                warning.check()
        return False

    def wait_for_inputs(self, limit, log_name):
        """Before joining: wait up to ``limit`` wall s until every
        connection this node's counted messages travel on is up at both
        ends, warning of those that are not. A message published before
        its connection never arrives; and rospy's publisher answers a new
        subscriber before it adds the connection to those it writes to,
        so a subscriber can count itself connected while messages
        published meanwhile never reach it. Either way one that a grant
        counts would be waited for in vain. So, by the master's graph and
        the members a grant names (one is seen first, unless none comes
        within FIRST_GRANT s of the owner's connection: time is held for
        a first member, and there is none):

        - each input is connected to every node that publishes it, and
          has had a message from each member among them (which was then
          writing to it);
        - each topic this node publishes has, at the publisher's end, a
          connection to every member that subscribes to it.

        Those counted before the first grant are never awaited
        (MessageLedger.settle)."""
        deadline = time.monotonic() + limit
        owner_since = None  # wall s since the owner is connected
        while not rospy.is_shutdown():
            graph = topic_graph()
            publishers, subscribers = graph[:2] if graph else ({}, {})
            members = self.receiver.named()
            now = time.monotonic()
            if owner_since is None and self.receiver.sub.get_num_connections():
                owner_since = now
            held = owner_since is not None and now - owner_since > FIRST_GRANT
            waiting = [] if members or held else ['a first grant on %s' % GRANT_TOPIC]
            waiting += self._unconnected(members, publishers, subscribers)
            if not waiting:
                return
            if now > deadline:
                rospy.logwarn('%s: after %.0f s, still not connected for %s; '
                              'joining the lockstep without it', log_name,
                              limit, '; '.join(waiting))
                return
            rospy.rostime.wallsleep(0.05)

    def _unconnected(self, members, publishers, subscribers):
        """What wait_for_inputs still waits for, by the master's graph
        (``publishers``, ``subscribers``: topic -> nodes) and ``members``."""
        waiting = []
        for topic in sorted(self.inputs.ledger.topics):
            listed = set(publishers.get(topic, ())) - {self.name}
            missing = ((listed - connected_publishers(topic))
                       | (listed & members - connected_publishers(topic, delivering=True)))
            if missing:
                waiting.append('%s from %s' % (topic, ', '.join(sorted(missing))))
        for topic in sorted(subscribers):
            conns = published_connections(topic)
            if conns is None:
                continue
            missing = ((set(subscribers[topic]) & members) - {self.name}
                       - {subscriber_name(c) for c in conns})
            if missing:
                waiting.append('%s to %s' % (topic, ', '.join(sorted(missing))))
        return waiting
