"""A lockstep member's reports to the owner: the step it handled, its
next tick and the messages it published (a part of
rbx1_nav.sim_time.member_ros.Member). Whether the node is a member at
all (joined, left) is kept here: a report is what makes it one.
"""
import threading

from rbx1_nav.common.publish_ros import from_ns, publish, synchronous_publisher
from rbx1_nav.msg import LockstepReport

#: A global topic, like /clock: one owner of simulated time per master.
REPORT_TOPIC = '/lockstep_report'


class Reports(object):
    """A member's reports: each counts the messages published so far
    (:meth:`sent`, :meth:`publisher`), so the members reading them wait
    for them; the last one is kept to send again."""

    def __init__(self, follower, every_step, passive):
        self.follower = follower
        self.every_step = every_step
        self.passive = passive
        self.sent_counts = {}  # topic -> messages published
        # Orders the reports (report, leave from a shutdown hook, the
        # re-sends) apart from the member's condition: the next grant can
        # arrive before the report's send returns (this thread preempted
        # by the owner it woke), and must not wait for it.
        self.sending = threading.RLock()
        self.joined = self.left = False
        self.last = None        # the last report, to send again
        self.pub = synchronous_publisher(REPORT_TOPIC, LockstepReport)

    def start(self):
        """Joined: the first report answers the step last handled (0 if none)."""
        self.joined, self.left = True, False
        self.report(self.follower.handled or 0, 0)

    def send_again(self):
        """The last report again (a grant repeated, a new owner, none for a while)."""
        with self.sending:
            if self.joined and self.last is not None:
                publish(self.pub, self.last)

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


class CountedPublisher(object):
    """A member's publisher (:meth:`Reports.publisher`): synchronous, and
    every message counted in the member's reports, so the members that
    read the topic wait for it."""

    def __init__(self, reports, topic, msg_class):
        self.reports = reports
        self.pub = synchronous_publisher(topic, msg_class)
        self.resolved_name = self.pub.resolved_name

    def publish(self, msg):
        publish(self.pub, msg)
        self.reports.sent(self.resolved_name)

    def get_num_connections(self):
        return self.pub.get_num_connections()
