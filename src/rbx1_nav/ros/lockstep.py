"""The ROS side of lockstep simulated time (the rules: rbx1_nav.lockstep).

Lockstep is on when both ``/use_sim_time`` and ``/lockstep`` are true
(sim_clock.launch sets them); on a real robot nothing here runs.

:class:`Keeper` is a gate's owner (sim_clock, a simulator): it takes the
members' reports and waits until simulated time may move on.
:class:`Reporter` is a member (a simulator, a motion node): it joins,
reports each step it handled, and leaves.
"""
import threading
import time
import warnings

import rospy
from std_srvs.srv import Trigger, TriggerResponse

from rbx1_nav.lockstep import Gate
from rbx1_nav.msg import Lockstep

#: Relative topic on which motion nodes report to their simulator.
NODE_TOPIC = 'lockstep'
#: Relative service (std_srvs/Trigger) through which a motion node joins
#: its simulator's lockstep; the answer's message is the first tick (ns).
JOIN_SERVICE = 'lockstep_join'
#: Wall seconds a join may wait for the simulator's next step.
JOIN_LIMIT = 10.0
#: Global topic on which simulators report to sim_clock (one clock serves
#: every namespace, like /clock itself).
CLOCK_TOPIC = '/clock_lockstep'
#: Wall seconds a keeper waits for a member before saying who it waits for.
SLOW_MEMBER = 1.0
#: Wall seconds after which commands a member reported are taken as lost
#: (a connection that dropped them), so time does not stop for good.
LOST_COMMANDS = 1.0
#: Wall seconds a member may hold time without a report before it is
#: dropped (it rejoins with its next report): a stuck member must not stop
#: every node's clock for good.
SILENT_MEMBER = 3.0


def enabled():
    """True when this run uses lockstep simulated time."""
    return bool(rospy.get_param('/use_sim_time', False)
                and rospy.get_param('/lockstep', False))


def to_ns(stamp):
    """rospy.Time -> integer nanoseconds."""
    return stamp.secs * 1000000000 + stamp.nsecs


def from_ns(ns):
    """Integer nanoseconds -> rospy.Time."""
    return rospy.Time(*divmod(int(ns), 1000000000))


def sleep_until(time_ns, since):
    """Sleep until ROS time reaches ``time_ns``; ``since`` (ns) is the time
    the caller last handled. Raises ROSTimeMovedBackwardsException if ROS
    time is already back before ``since`` (a new clock, from further back),
    as rospy.sleep does when time moves back during the sleep."""
    now = to_ns(rospy.Time.now())
    if now < since:
        raise rospy.ROSTimeMovedBackwardsException((since - now) * 1e-9)
    rospy.sleep(from_ns(time_ns) - from_ns(now))


def sender(msg):
    """The node name that published ``msg`` (rospy keeps it per message)."""
    return msg._connection_header['callerid']


def synchronous_publisher(topic, msg_class):
    """A publisher that writes each message before publish() returns, with
    no Nagle delay: lockstep waits for every message, so a hand-off to
    rospy's queue thread would only add latency to each step."""
    with warnings.catch_warnings():  # queue_size None is the point here
        warnings.simplefilter('ignore', SyntaxWarning)
        return rospy.Publisher(topic, msg_class, queue_size=None,
                               tcp_nodelay=True)


class Keeper(object):
    """Owner of a lockstep gate: members report to it on ``topic``; with
    ``join_service``, motion nodes join through that service."""

    def __init__(self, owner, topic, join_service=None):
        self.owner = owner  # for log lines
        self.gate = Gate()
        self.cond = threading.Condition()
        self.pending, self.admitted = [], {}  # joins: waiting, granted (ns)
        self.seen = set()  # members whose report connection was seen
        self.sub = rospy.Subscriber(topic, Lockstep, self._on_report,
                                    queue_size=None, tcp_nodelay=True)
        if join_service:
            rospy.Service(join_service, Trigger, self._on_join)

    def _on_join(self, request):
        """A node asks to join: answer after the next step, its first tick."""
        name = sender(request)
        with self.cond:
            self.admitted.pop(name, None)
            self.pending.append(name)
            self.cond.wait_for(lambda: name in self.admitted or rospy.is_shutdown(),
                               JOIN_LIMIT)
            tick = self.admitted.pop(name, None)
        if tick is None:
            return TriggerResponse(False, '%s did not step within %g s'
                                   % (self.owner, JOIN_LIMIT))
        rospy.loginfo('%s: %s joined lockstep', self.owner, name)
        return TriggerResponse(True, str(tick))

    def admit(self, time_ns):
        """Right after a step at ``time_ns``: grant the waiting joins."""
        with self.cond:
            for name in self.pending:
                self.gate.admit(name, time_ns)
                self.admitted[name] = time_ns
            self.pending = []
            self.cond.notify_all()

    def _on_report(self, msg):
        name = sender(msg)
        with self.cond:
            change = self.gate.report(name, to_ns(msg.handled), to_ns(msg.next),
                                      msg.commands)
            self.cond.notify_all()
        if change:
            rospy.loginfo('%s: %s %s lockstep', self.owner, name, change)

    def command_from(self, msg):
        """Count a cmd_vel message (call from the cmd_vel callback)."""
        with self.cond:
            self.gate.command_from(sender(msg))
            self.cond.notify_all()

    def next_tick(self):
        """Earliest next tick of a member (ns), or None without members."""
        with self.cond:
            return self.gate.next_tick()

    def has_members(self):
        with self.cond:
            return bool(self.gate.members)

    def _drop_disconnected(self):
        """Members whose connection closed (the node died) leave the gate."""
        connected = {c.callerid_pub for c in self.sub.impl.connections}
        self.seen |= connected & set(self.gate.members)
        # A member that just joined may not have its connection listed yet.
        for name in self.gate.keep_only(connected | (set(self.gate.members) - self.seen)):
            self.seen.discard(name)
            rospy.logwarn('%s: %s left lockstep without a word (node gone)',
                          self.owner, name)

    def wait_allows(self, time_ns):
        """Wait (wall time) until simulated time may reach ``time_ns``.

        Returns False if the node shuts down first. Every SLOW_MEMBER wall
        seconds of waiting it logs who it waits for.
        """
        started = time.monotonic()
        warn_at = started + SLOW_MEMBER
        with self.cond:
            while not rospy.is_shutdown():
                if self.gate.allows(time_ns):
                    return True
                self.cond.wait(0.05)
                if self.gate.blocking(time_ns):
                    self._drop_disconnected()
                if time.monotonic() - started > LOST_COMMANDS:
                    for name in self.gate.missing_commands(time_ns):
                        rospy.logwarn('%s: cmd_vel messages from %s lost on the '
                                      'way (%r); going on without them',
                                      self.owner, name, self.gate.members[name])
                        self.gate.forgive(name)
                if time.monotonic() - started > SILENT_MEMBER:
                    for name in self.gate.blocking(time_ns):
                        rospy.logwarn('%s: %s has held simulated time at %.3f s for '
                                      '%.0f s without a report; going on without it '
                                      'until it reports again', self.owner, name,
                                      time_ns * 1e-9, SILENT_MEMBER)
                        self.gate.leave(name)
                if time.monotonic() > warn_at:
                    warn_at += SLOW_MEMBER
                    rospy.logwarn('%s: simulated time waits at %.3f s for %s',
                                  self.owner, time_ns * 1e-9, ', '.join(
                                      '%s (%r)' % (name, self.gate.members[name])
                                      for name in self.gate.blocking(time_ns)))
        return False


class JoinError(Exception):
    """A node could not join the lockstep; the message says why."""


class Reporter(object):
    """A lockstep member: reports the steps it handled on ``topic``."""

    def __init__(self, topic):
        self.pub = synchronous_publisher(topic, Lockstep)
        self.commands = 0  # cmd_vel messages since joining (motion nodes)
        self.joined = False
        self.left = False  # after leave(), until join(): no more reports

    def listeners(self):
        """Node names of the gate's owners that take these reports."""
        return {c.endpoint_id for c in self.pub.impl.connections}

    def connected(self):
        """True once the gate's owner listens (a report would arrive)."""
        return bool(self.listeners())

    def join(self, wait):
        """Join the simulator's lockstep through JOIN_SERVICE, waiting up to
        ``wait`` wall seconds for it; the first tick (ns): a step the
        simulator has just published and for which it waits. Commands
        count from here. Raises JoinError saying why it could not."""
        join = rospy.ServiceProxy(JOIN_SERVICE, Trigger)
        deadline = time.monotonic() + wait
        while not self.connected():  # a report sent before is lost
            if time.monotonic() > deadline or rospy.is_shutdown():
                raise JoinError('nothing takes lockstep reports on %s after '
                                '%.1f s' % (self.pub.resolved_name, wait))
            rospy.rostime.wallsleep(0.01)
        try:
            join.wait_for_service(max(0.1, deadline - time.monotonic()))
            self.commands = 0
            self.joined, self.left = True, False
            answer = join()
        except (rospy.ROSException, rospy.ServiceException) as err:
            raise JoinError('the simulator\'s %s service does not answer (%s)'
                            % (join.resolved_name, err))
        if not answer.success:
            raise JoinError(answer.message)
        tick = int(answer.message)
        # This node's /clock may lag the simulator's by a message: its time
        # must reach the tick before it handles it (or it would look like
        # time moving back).
        while to_ns(rospy.Time.now()) < tick and not rospy.is_shutdown():
            if time.monotonic() > deadline + JOIN_LIMIT:
                raise JoinError('this node\'s clock did not reach the first tick')
            rospy.rostime.wallsleep(0.0005)
        return tick

    def ticks(self, rate, wait):
        """Join, then yield each tick (ns) at ``rate`` Hz; after each, report
        it handled and sleep to the next."""
        period = int(round(1e9 / rate))
        tick = self.join(wait)
        while not rospy.is_shutdown():
            yield tick
            self.report(tick, tick + period)
            sleep_until(tick + period, since=tick)
            tick += period

    def report(self, handled_ns, next_ns):
        """Handled ``handled_ns``; time must not pass ``next_ns`` before the
        next report. A simulator's first report joins the clock; after
        leave() (a shutdown hook, from another thread) none goes out, so a
        node on its way out cannot join again."""
        if self.left:
            return
        self.joined = True
        self.pub.publish(Lockstep(handled=from_ns(handled_ns),
                                  next=from_ns(next_ns),
                                  commands=self.commands))

    def leave(self, handled_ns):
        """Leave the lockstep (no-op when not a member, or after shutdown)."""
        if not self.joined:
            return
        self.joined, self.left = False, True
        try:
            self.pub.publish(Lockstep(handled=from_ns(handled_ns),
                                      commands=self.commands))
        except rospy.ROSException:  # topics closed by shutdown: the
            pass                    # closing connection says it instead
