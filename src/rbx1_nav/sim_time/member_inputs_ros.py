"""A lockstep member's inputs: the messages it receives, counted against
those each grant says were sent, and held until a grant counts them (a
part of rbx1_nav.sim_time.member_ros.Member; the counting's rules:
rbx1_nav.sim_time.member.MessageLedger and Inbox).
"""
import time

import rospy

from rbx1_nav.sim_time.member import (LOST_MESSAGES, POLL, STALLED, WAIT_WARNING, Inbox,
                                      MessageLedger)
from rbx1_nav.common.publish_ros import delivered, link, to_ns
from rbx1_nav.common.master_ros import node_answers, topic_graph
from rbx1_nav.common.rospy_private_ros import publisher_name, sender, subscribed_connections


def connected_publishers(topic, delivering=False):
    """The nodes this node is connected to as a subscriber of ``topic``
    (resolved); with ``delivering``, only those a member's message has
    come from on the connection (:func:`rbx1_nav.common.publish_ros.delivered`)."""
    return {publisher_name(c) for c in subscribed_connections(topic) or ()
            if not delivering or delivered(c)}


class CountedInputs(object):
    """The messages arriving on ``inputs`` (resolved topics), counted with
    :meth:`arrived`; with ``hold``, each one's item is kept until a grant
    counts it (:meth:`take`). ``cond`` is the member's condition, shared
    with its grants: an arrival wakes whatever the member waits for.
    ``reports`` says whether the node is a member (a Reports)."""

    def __init__(self, name, cond, reports, inputs, hold):
        self.name = name
        self.cond = cond
        self.reports = reports
        self.inbox = Inbox(inputs) if hold else None
        self.ledger = self.inbox.ledger if hold else MessageLedger(inputs)
        self.settled = False   # a first grant's counts settled

    def wait_counted(self, grant):
        """Before handling ``grant``: wait (wall time) until every message
        it counts on this member's inputs has arrived. A counted message
        was sent before the grant, on a connection that delivers in
        order: it is awaited as long as its sender stays connected,
        however loaded the machine (a warning every WAIT_WARNING s, and
        after STALLED s, a backstop, it is taken as lost). The missing
        messages of a sender unconnected for LOST_MESSAGES s that no
        longer publishes the topic, or no longer answers (killed), are
        taken as lost, with a warning."""
        counts = list(zip(grant.topics, grant.senders, grant.counts))
        with self.cond:
            if not self.settled:
                self.ledger.settle(counts)
                self.settled = True
            self.ledger.restarts(counts)
        away = {}  # (topic, sender) -> wall s since it is unconnected
        started = time.monotonic()
        warn_at = started + WAIT_WARNING
        while not rospy.is_shutdown():
            with self.cond:
                missing = self.ledger.missing(counts)
                if missing:
                    self.cond.wait(POLL)
                    missing = self.ledger.missing(counts)
            if not missing:
                return
            now = time.monotonic()
            stalled = now - started > STALLED
            gone = None if stalled else _senders_gone(missing, away, now)
            with self.cond:
                lost = self.ledger.give_up(counts, gone)
            for topic, name, short in lost:
                rospy.logwarn('%s: %d message(s) from %s on %s lost on the way (%s); '
                              'going on without them', self.name, short, name, topic,
                              'not come in %.0f s' % STALLED if stalled
                              else '%s is gone' % name)
            if now > warn_at and not lost:
                warn_at = now + WAIT_WARNING
                rospy.logwarn('%s: still waiting for %s, sent before the step at '
                              '%.3f s', self.name, '; '.join(
                                  '%d message(s) from %s on %s' % (short, name, topic)
                                  for topic, name, short in missing),
                              to_ns(grant.time) * 1e-9)

    def arrived(self, topic, msg, item=None):
        """Count a message that arrived on ``topic`` (an input); with
        ``hold``, keep ``item`` (what the member needs of it) for :meth:`take`
        while a member (a course between two runs keeps nothing). True if
        it is kept."""
        with self.cond:
            kept = self.inbox is not None and self.reports.joined
            if self.inbox is None:
                self.ledger.arrived(topic, sender(msg), link(msg))
            elif kept:
                self.inbox.arrived(topic, sender(msg), item, link(msg))
            else:
                self.inbox.passed(topic, sender(msg), link(msg))
            self.cond.notify_all()
        return kept

    def take(self, grant, key, topic=None):
        """With ``hold``: the items of the messages ``grant`` counts on the
        inputs (on ``topic`` only, if given; waited for as
        :meth:`wait_counted` does), in the order of ``key(item)``: the same
        on every run (rbx1_nav.sim_time.member.Inbox)."""
        self.wait_counted(grant)
        with self.cond:
            return self.inbox.take(zip(grant.topics, grant.senders, grant.counts),
                                   set(grant.members), key, topic)


def _senders_gone(missing, away, now):
    """The (topic, sender) pairs of ``missing`` ((topic, sender, count))
    whose messages will never come: the sender has been unconnected for
    LOST_MESSAGES s, and the master no longer lists it as a publisher of
    the topic or it does not answer (killed). One still there is
    connecting (started again under its name): waited for. ``away``
    keeps since when each is unconnected."""
    waiting = {(topic, name) for topic, name, _ in missing}
    for key in set(away) - waiting:
        del away[key]
    for topic, name in waiting:
        if name in connected_publishers(topic):
            away.pop((topic, name), None)
        else:
            away.setdefault((topic, name), now)
    overdue = [key for key, since in away.items() if now - since > LOST_MESSAGES]
    if not overdue:
        return set()
    graph = topic_graph()
    publishers = graph[0] if graph else {}
    gone = set()
    for topic, name in overdue:
        if name in publishers.get(topic, ()) and node_answers(name):
            away[(topic, name)] = now
        else:
            gone.add((topic, name))
    return gone
