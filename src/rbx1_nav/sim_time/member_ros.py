"""A lockstep member's ROS side (its rules: rbx1_nav.sim_time.member).

Lockstep is on when both ``/use_sim_time`` and ``/lockstep`` are true
(sim_clock.launch sets them); on a real robot nothing here runs.
:class:`Member` is a simulator's, a motion node's, a filter's or a bag
player's part: it joins, waits for each grant naming it, reports the step
handled with the messages it published (:meth:`Member.publisher`), and
leaves. The owner
that grants the steps is rbx1_nav.sim_time.lockstep_ros.TimeOwner.
"""
import threading
import time

import rospy

from rbx1_nav.sim_time.member import (LOST_MESSAGES, REPEAT, RESEND, STALE, STALLED,
                                      WAIT_WARNING, Follower, Inbox, MessageLedger, Reminder)
from rbx1_nav.common.publish_ros import (delivered, from_ns, keep_own_time, link, publish,
                                         synchronous_publisher, to_ns)
from rbx1_nav.common.master_ros import node_answers, topic_graph
from rbx1_nav.common.rospy_private_ros import (published_connections, publisher_name, sender,
                                              set_rostime, subscribed_connections,
                                              subscriber_name)
from rbx1_nav.msg import LockstepGrant, LockstepReport

__all__ = ['GRANT_TOPIC', 'REPORT_TOPIC', 'GRANT_LIMIT', 'POLL', 'STALLED',
           'NO_OWNER_WARNING', 'NO_OWNER_REMINDER', 'no_owner_text', 'NoOwnerWarning',
           'connected_publishers', 'JoinError',
           'Member', 'CountedPublisher']

#: Global topics, like /clock: one owner of simulated time per master.
GRANT_TOPIC = '/lockstep_grant'
REPORT_TOPIC = '/lockstep_report'
#: Wall seconds after its last step a motion node takes the clock as gone
#: if no owner is connected (sim_clock gone; a new one may take over
#: meanwhile). While the owner is connected it waits however
#: long time takes: time waits for the slowest member (sim_clock names it
#: every second), and a loaded machine only makes a step take longer.
GRANT_LIMIT = 4.0
#: Wall seconds a member about to join waits for a first grant, once the
#: owner is connected, to learn who the members are (grants go out every
#: step while there are any).
FIRST_GRANT = 1.0
#: Wall seconds between a waiting member's checks that what it waits for
#: is still connected.
POLL = 0.1
#: Wall seconds a simulator, filter or bag player waits for a grant before
#: it says that nothing grants steps, and between its reminders after.
NO_OWNER_WARNING = 5.0
NO_OWNER_REMINDER = 60.0


def no_owner_text(log_name, waited):
    """The warning of a member that nothing grants steps to, ``waited``
    wall seconds into its wait."""
    return ('%s: simulated time is set (/use_sim_time and /lockstep true) '
            'but nothing has granted a step on %s for %.0f s: no sim_clock '
            'runs. For real time, `rosparam set /use_sim_time false` and start '
            'this again (left true by a launch with sim_speed that was killed, '
            'or by rosparam set); for simulated time, roslaunch rbx1_nav '
            'sim_clock.launch' % (log_name, GRANT_TOPIC, waited))


class NoOwnerWarning(object):
    """A member's warnings while nothing grants it steps (Reminder)."""

    def __init__(self, log_name):
        self.log_name = log_name
        self.reminder = Reminder(NO_OWNER_WARNING, NO_OWNER_REMINDER,
                                 time.monotonic())

    def granted(self):
        self.reminder.granted(time.monotonic())

    def check(self):
        waited = self.reminder.due(time.monotonic())
        if waited is not None and not rospy.is_shutdown():
            rospy.logwarn(no_owner_text(self.log_name, waited))


def connected_publishers(topic, delivering=False):
    """The nodes this node is connected to as a subscriber of ``topic``
    (resolved); with ``delivering``, only those a member's message has
    come from on the connection (:func:`rbx1_nav.common.publish_ros.delivered`)."""
    return {publisher_name(c) for c in subscribed_connections(topic) or ()
            if not delivering or delivered(c)}


def owners_alive():
    """The nodes registered as publishing grants that answer (a killed one
    stays registered)."""
    graph = topic_graph()
    publishers = graph[0].get(GRANT_TOPIC, ()) if graph else ()
    return [name for name in sorted(publishers) if node_answers(name)]


class JoinError(Exception):
    """A node could not join the lockstep; the message says why."""


class Member(object):
    """A lockstep member: a simulator (``every_step``), a motion node, a
    filter or a bag player.

    A member passes the resolved names of the topics whose counted
    messages it awaits in ``inputs`` (a simulator its cmd_vel topics) and
    counts each message that arrives on them with :meth:`arrived`; with
    ``hold`` it keeps each one until a grant counts it (:meth:`take`). A
    member counts each message it publishes with :meth:`sent` (or through
    :meth:`publisher`). Once it has joined, a simulator takes its ROS time from
    the grants, not /clock (:func:`keep_own_time`): it is named in every
    grant, and /clock moves only with them.

    A motion node waits for each of its ticks with :meth:`wait_grant`. A
    simulator passes ``step``: step(action, time ns, items) steps to a
    granted time (action HANDLE or BACK, as wait_grant returns) and
    returns its next tick (ns); :meth:`serve` then runs it. With ``hold``
    ``items`` are those of the messages the grant counts (:meth:`take`),
    per sender in their order of arrival; otherwise none.
    """

    def __init__(self, every_step=False, inputs=(), step=None, hold=False,
                 passive=False):
        self.name = rospy.get_name()
        self.every_step = every_step
        self.passive = passive
        self.step = step
        self.busy = False       # a step being handled (serve)
        self.heard = None       # wall time of the last grant or step handled
        self.failure = None     # what step raised, for serve to raise
        self.follower = Follower()
        self.inbox = Inbox(inputs) if hold else None
        self.ledger = self.inbox.ledger if hold else MessageLedger(inputs)
        self.sent_counts = {}  # topic -> messages published
        self.settled = False   # a simulator's first grant handled
        self.cond = threading.Condition()
        # Orders the reports (report, leave from a shutdown hook, the
        # re-sends) apart from self.cond: the next grant can arrive before
        # the report's send returns (this thread preempted by the owner it
        # woke), and must not wait for it.
        self.sending = threading.RLock()
        self.grant = None       # the newest grant naming this node
        self.members = set()    # the names in the newest grant seen
        self.sims = set()       # the simulators it names
        self.joined = self.left = False
        self.rejoin = False     # a new owner is there: send the report now
        self.last = None        # the last report, to send again
        self.own_time = False   # ROS time set from the grants (a simulator)
        self.pub = synchronous_publisher(REPORT_TOPIC, LockstepReport)
        self.sub = rospy.Subscriber(GRANT_TOPIC, LockstepGrant, self._on_grant,
                                    queue_size=None, tcp_nodelay=True)

    def _on_grant(self, msg):
        with self.cond:
            self.members = set(msg.members)
            self.sims = set(msg.simulators)
            named = self.name in self.members
            if named and self.step is None:
                self.grant = msg
                self.cond.notify_all()
            elif named:
                self.busy = True
            elif self.joined and msg.session != self.follower.session:
                # A new owner (sim_clock restarted): join it at once.
                self.rejoin = True
                self.cond.notify_all()
        if named and self.step is not None:
            self._handle(msg)

    def _handle(self, grant):
        """A simulator's step, in the thread that received its grant (see
        serve): the commands counted, the step, the report."""
        try:
            taken = self.failure is None and self._take(grant)
            if taken:
                action, time_ns, _ = taken
                if self.inbox is None:
                    self.wait_counted(grant)
                    held = []
                else:  # a simulator's commands: per sender, as they came
                    held = self.take(grant, key=lambda item: 0)
                self.report(time_ns, self.step(action, time_ns, held))
        except Exception as err:  # serve raises it in the node's own thread
            with self.cond:
                self.failure = err
                self.cond.notify_all()
        self.heard = time.monotonic()
        self.busy = False  # no notify: a wake-up of serve's thread every step

    def serve(self, warning):
        """A simulator's loop, until shutdown or an error of ``step`` (raised
        here). Each step runs in the thread that receives the grants: a
        hand-off to this one would cost every step a thread woken (tens of
        microseconds on a virtual machine). Meanwhile this
        thread sends the last report again every RESEND wall seconds
        without a grant (at once when a new owner appears) and warns
        (``warning``, a NoOwnerWarning) while it gets none."""
        while not rospy.is_shutdown():
            with self.cond:
                self.cond.wait_for(
                    lambda: self.rejoin or self.failure is not None, RESEND)
                if self.failure is not None:
                    raise self.failure
                rejoin, self.rejoin = self.rejoin, False
                now = time.monotonic()
                quiet = not self.busy and now - self.heard > RESEND
            if rejoin or quiet:
                self._send_again()
            if quiet:
                warning.check()
            else:
                warning.granted()
        deadline = time.monotonic() + LOST_MESSAGES
        while self.busy and time.monotonic() < deadline:  # a step under way ends
            rospy.rostime.wallsleep(0.01)                  # before the node does

    def simulators(self):
        """The simulators taking part, as the newest grant names them."""
        with self.cond:
            return set(self.sims)

    def connected(self):
        """True once the owner takes this node's reports and sends it grants."""
        return bool(self.pub.get_num_connections() and self.sub.get_num_connections())

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
        with self.cond:
            self.grant = None
            self.heard = time.monotonic()
        if self.every_step and not self.own_time:
            self.own_time = keep_own_time()
        self.joined, self.left = True, False
        self.report(self.follower.handled or 0, 0)

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
            with self.cond:
                members = set(self.members)
            now = time.monotonic()
            if owner_since is None and self.sub.get_num_connections():
                owner_since = now
            held = owner_since is not None and now - owner_since > FIRST_GRANT
            waiting = [] if members or held else ['a first grant on %s' % GRANT_TOPIC]
            for topic in sorted(self.ledger.topics):
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
            if not waiting:
                return
            if now > deadline:
                rospy.logwarn('%s: after %.0f s, still not connected for %s; '
                              'joining the lockstep without it', log_name,
                              limit, '; '.join(waiting))
                return
            rospy.rostime.wallsleep(0.05)

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

    def grants(self, log_name):
        """(action, time ns, grant) of each step granted to a member no
        robot waits on (a filter, a bag player), until shutdown; a warning
        NO_OWNER_WARNING s into a wait without one, then every
        NO_OWNER_REMINDER s."""
        warning = NoOwnerWarning(log_name)
        while not rospy.is_shutdown():
            granted = self.wait_grant(NO_OWNER_WARNING)
            if granted is not None:
                warning.granted()
                yield granted
            else:
                warning.check()

    def wait_grant(self, limit=None):
        """Wait for the next step granted to this node; return (action,
        time ns, grant): action HANDLE or BACK (rbx1_nav.sim_time.member.Follower).
        Sends the last report again every RESEND wall seconds without a
        grant (at once to a new owner). While an owner is connected it
        waits however long the step takes; None once no owner is
        connected ``limit`` wall seconds after the wait began (the last
        step handled), or at shutdown.
        """
        started = time.monotonic()
        resend = started + RESEND
        while not rospy.is_shutdown():
            with self.cond:
                self.cond.wait_for(lambda: self.grant is not None or self.rejoin, POLL)
                grant, self.grant = self.grant, None
                rejoin, self.rejoin = self.rejoin, False
            if grant is None:
                now = time.monotonic()
                if (limit is not None and now - started > limit
                        and not self.sub.get_num_connections()):
                    return None
                if rejoin or now > resend:
                    resend = now + RESEND
                    self._send_again()
                continue
            taken = self._take(grant)
            if taken:
                return taken
        return None

    def _take(self, grant):
        """(action, time ns, grant) of a grant to handle; None for one
        already handled (the report goes again) or stale (refused)."""
        time_ns = to_ns(grant.time)
        action = self.follower.grant(grant.session, time_ns)
        if action == REPEAT:
            self._send_again()
        elif action == STALE:
            rospy.logwarn('%s: lockstep grant at %.3f s is before the step '
                          'already handled (%.3f s): refused', self.name,
                          time_ns * 1e-9, self.follower.handled * 1e-9)
        else:
            if self.own_time:
                set_rostime(grant.time)
            return action, time_ns, grant
        return None

    def _send_again(self):
        with self.sending:
            if self.joined and self.last is not None:
                publish(self.pub, self.last)

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
            kept = self.inbox is not None and self.joined
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

    def sent(self, topic):
        """Count a message this member published on ``topic`` (resolved)."""
        self.sent_counts[topic] = self.sent_counts.get(topic, 0) + 1

    def publisher(self, topic, msg_class):
        """A publisher on ``topic`` whose every message is written before
        publish() returns and counted in this member's reports."""
        return CountedPublisher(self, topic, msg_class)

    def report(self, handled_ns, next_ns, leaving=False):
        """Handled ``handled_ns``; ``next_ns`` its next tick. After leave()
        (a shutdown hook, from another thread) none goes out, so a node on
        its way out cannot join again."""
        with self.sending:  # not interleaved with leave() from another thread
            if self.left:
                return
            self.follower.handled_step(handled_ns or None)
            topics = sorted(self.sent_counts)
            self.last = LockstepReport(
                handled=from_ns(handled_ns), next=from_ns(next_ns),
                every_step=self.every_step, leaving=leaving, passive=self.passive,
                topics=topics,
                counts=[self.sent_counts[t] for t in topics])
            publish(self.pub, self.last)

    def leave(self):
        """Leave the lockstep (a no-op when not a member): the last report
        carries the commands sent, so the simulator still waits for them."""
        with self.sending:
            if not self.joined:
                return
            self.report(self.follower.handled or 0, 0, leaving=True)
            self.joined, self.left = False, True


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


class CountedPublisher(object):
    """A member's publisher (:meth:`Member.publisher`): synchronous, and
    every message counted in the member's reports, so the members that
    read the topic wait for it."""

    def __init__(self, member, topic, msg_class):
        self.member = member
        self.pub = synchronous_publisher(topic, msg_class)
        self.resolved_name = self.pub.resolved_name

    def publish(self, msg):
        publish(self.pub, msg)
        self.member.sent(self.resolved_name)

    def get_num_connections(self):
        return self.pub.get_num_connections()
