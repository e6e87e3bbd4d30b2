"""sim_clock's side of lockstep simulated time (the rules:
rbx1_nav.sim_time.lockstep; a member's side: rbx1_nav.sim_time.member_ros).

:class:`TimeOwner` takes the members' reports on REPORT_TOPIC, grants each
step on GRANT_TOPIC and publishes ``/clock`` (:class:`ClockPublisher`).
"""
import random
import threading
import time

import rospy
from rosgraph_msgs.msg import Clock

from rbx1_nav.sim_time.member import RESEND, Report
from rbx1_nav.sim_time.member_grants_ros import GRANT_TOPIC
from rbx1_nav.sim_time.member_reports_ros import REPORT_TOPIC
from rbx1_nav.common.publish_ros import (from_ns, keep_own_time, publish,
                                         synchronous_publisher, to_ns)
from rbx1_nav.common.rospy_private_ros import (connections, publisher_name, sender,
                                              set_rostime)
from rbx1_nav.msg import LockstepGrant, LockstepReport
from rbx1_nav.sim_time.lockstep import Owner

__all__ = ['FIRST_MEMBER', 'ClockPublisher', 'TimeOwner']

#: Wall seconds between the owner's lines naming the members it waits for.
SLOW_MEMBER = 1.0
#: Wall seconds sim_clock holds time at its start for a first member (a
#: simulator joins within a second; one of a sim_clock started again
#: joins once the new connections are up: over 5 s beside a loaded
#: test suite).
FIRST_MEMBER = 15.0


class ClockPublisher(object):
    """/clock, from the one node that publishes it: its own ROS time
    follows what it publishes instead of coming back over /clock
    (:func:`keep_own_time`)."""

    def __init__(self):
        self.pub = synchronous_publisher('/clock', Clock)
        self.own_time = keep_own_time()

    def publish(self, time_ns):
        """Publish ``time_ns``; False once rospy has closed its topics."""
        stamp = from_ns(time_ns)
        if self.own_time:
            set_rostime(stamp)
        return publish(self.pub, Clock(clock=stamp))


class TimeOwner(object):
    """sim_clock's side of lockstep: the one owner of simulated time.

    ``start`` and ``step`` (ns): the time already reached and the step
    taken when no member asks for a time; ``batch``: grant simulators only
    the motion nodes' ticks while any takes part (rbx1_nav.sim_time.lockstep).
    """

    def __init__(self, start, step, batch=False, name='sim_clock'):
        self.name = name
        self.owner = Owner(start, step, batch)
        self.session = random.getrandbits(63) or 1
        self.cond = threading.Condition()
        self.seen = set()  # members whose report connection was listed
        self.plan = None      # sim_clock's pacing (run)
        self.planned = None   # (time ns, names, due wall s): the next step
        self.current = None   # (time ns, re-send at, warn at) of the step granted
        # Taken under self.cond when a step starts, released once its grant
        # and /clock are out: whichever thread sends them, a step's go out
        # before the next one's.
        self.sending = threading.Lock()
        self.clock = ClockPublisher()
        self.grant_pub = synchronous_publisher(GRANT_TOPIC, LockstepGrant)
        self.sub = rospy.Subscriber(REPORT_TOPIC, LockstepReport, self._on_report,
                                    queue_size=None, tcp_nodelay=True)

    def _on_report(self, msg):
        name = sender(msg)
        report = Report(name, to_ns(msg.handled), to_ns(msg.next), msg.every_step,
                        dict(zip(msg.topics, msg.counts)), msg.leaving, msg.passive)
        with self.cond:
            change, warning = self.owner.report(report)
            self.seen.add(name)  # its connection is listed: the report came over it
            start = self._next_step()
        if start:
            self._send_step(*start)
        if change:
            rospy.loginfo('%s: %s %s lockstep%s', self.name, name, change,
                          ' (simulator)' if msg.every_step and change == 'joined' else '')
        if warning:
            rospy.logwarn('%s: %s', self.name, warning)

    def _grant_message(self, time_ns, names):
        counts = self.owner.sent_counts()
        return LockstepGrant(
            session=self.session, time=from_ns(time_ns), members=names,
            simulators=self.owner.simulators(),
            topics=[c[0] for c in counts], senders=[c[1] for c in counts],
            counts=[c[2] for c in counts])

    def _send(self, time_ns, names):
        return publish(self.grant_pub, self._grant_message(time_ns, names))

    def wait_for_members(self, limit, count=1):
        """Wait up to ``limit`` wall seconds for ``count`` members, publishing
        meanwhile the start time on /clock (nodes wait for a first /clock
        before they join, and take it only once they have subscribed) and
        an empty grant (the members of an earlier sim_clock join at once
        when they see a new session). A graph whose members all join
        before time moves starts the same on every run (a bag's players,
        its filters). Fewer after ``limit``: time starts, with a warning."""
        deadline = time.monotonic() + limit
        with self.cond:
            while not (len(self.owner.members) >= count or rospy.is_shutdown()
                       or time.monotonic() > deadline):
                self.clock.publish(self.owner.now)
                self._send(self.owner.now, [])
                self.cond.wait(0.05)
            joined = sorted(self.owner.members)
        if 1 < count and len(joined) < count and not rospy.is_shutdown():
            rospy.logwarn('%s: %d of the %d lockstep members expected (~members) '
                          'joined within %.0f s (%s): starting time without the '
                          'others', self.name, len(joined), count, limit,
                          ', '.join(joined) or 'none')

    def run(self, plan):
        """Own simulated time until shutdown.

        ``plan(next_grant, drives)``, sim_clock's pacing, gives (time ns,
        names, wall s to wait) of the next step from the Owner's
        next_grant() and drives(). Each step is granted to its names and
        published on /clock; the next is planned once all have reported.
        The thread whose report completes a step starts the next one when
        its time has come (a hand-off to this thread would cost every step
        a thread woken); this thread starts the ones that wait, and
        watches the members: it re-sends a grant to the silent ones every
        RESEND s, names them every SLOW_MEMBER s, and drops those that
        died (their connection closed). A live member, however slow, is
        waited for: dropping it would make what the others see depend on
        the machine's load.
        """
        with self.cond:
            self.plan = plan
        while not rospy.is_shutdown():
            with self.cond:
                start = self._next_step()
                if not start:
                    due = self.planned[2] if self.planned else float('inf')
                    wait = min(0.05, max(0.0, due - time.monotonic()))
                    if not self.cond.wait(wait):
                        self._watch()
                    continue
            self._send_step(*start)

    def _next_step(self):
        """Under self.cond, once nothing is owed: plan the next step, and
        start it if its time has come; then return (time ns, grant or None)
        for the caller to send with _send_step, holding self.sending."""
        if self.plan is None or self.owner.owing():
            return None
        if self.planned is None:
            time_ns, names, wait = self.plan(self.owner.next_grant(), self.owner.drives())
            self.planned = (time_ns, names, time.monotonic() + wait)
        time_ns, names, due = self.planned
        now = time.monotonic()
        if now < due:
            self.cond.notify_all()  # run's thread starts it then
            return None
        self.planned = None
        names = self.owner.grant(time_ns, names)
        self.current = (time_ns, now + RESEND, now + SLOW_MEMBER)
        grant = self._grant_message(time_ns, names) if names else None
        self.sending.acquire()
        return time_ns, grant

    def _send_step(self, time_ns, grant):
        """The grant of a step just started, then its /clock (for everyone
        else: off the grant's path). Not under self.cond: a report that
        answers the grant before the send returns (this thread preempted
        by the member it woke) must not wait for it."""
        try:
            if grant is not None:
                publish(self.grant_pub, grant)
            self.clock.publish(time_ns)
        finally:
            self.sending.release()

    def _watch(self):
        """Under self.cond, every 50 ms (wall) while a step is owed: drop
        the members that died, re-send the grant to the silent ones every
        RESEND s, and say who time waits for every SLOW_MEMBER s."""
        if not self.owner.owing():
            return
        time_ns, resend_at, warn_at = self.current
        now = time.monotonic()
        self._drop_disconnected()
        owing = self.owner.owing()
        if owing and now > resend_at:
            resend_at = now + RESEND
            self._send(time_ns, owing)
        if owing and now > warn_at:
            warn_at = now + SLOW_MEMBER
            rospy.logwarn('%s: simulated time waits at %.3f s for %s',
                          self.name, time_ns * 1e-9, ', '.join(owing))
        self.current = (time_ns, resend_at, warn_at)

    def _drop_disconnected(self):
        """Members whose report connection closed (the node died) leave.
        Not while this node shuts down: rospy closes its connections then,
        after is_shutdown() turns true, and no member has gone."""
        connected = {publisher_name(c) for c in connections(self.sub)}
        if rospy.is_shutdown():
            return
        members = set(self.owner.members)
        self.seen |= connected & members
        # A member that just joined may not have its connection listed yet.
        for name in sorted((members & self.seen) - connected):
            self.seen.discard(name)
            self.owner.drop(name)
            rospy.logwarn('%s: %s left lockstep without a word (node gone)',
                          self.name, name)
