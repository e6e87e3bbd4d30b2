"""A lockstep member's ROS side (its rules: rbx1_nav.sim_time.member).

Lockstep is on when both ``/use_sim_time`` and ``/lockstep`` are true
(sim_clock.launch sets them); on a real robot nothing here runs.
:class:`Member` is a simulator's, a motion node's, a filter's or a bag
player's part: it joins, waits for each grant naming it, reports the step
handled with the messages it published (:meth:`Member.publisher`), and
leaves. The owner
that grants the steps is rbx1_nav.sim_time.lockstep_ros.TimeOwner.

A Member is the object its node holds; each of its methods is one of its
parts': Joining (member_join_ros), GrantReceiver (member_grants_ros),
CountedInputs (member_inputs_ros) and Reports (member_reports_ros).
"""
import threading

import rospy

from rbx1_nav.sim_time.member import POLL, STALLED, Follower
from rbx1_nav.sim_time.member_grants_ros import (GRANT_LIMIT, GRANT_TOPIC, NO_OWNER_REMINDER,
                                                 NO_OWNER_WARNING, GrantReceiver,
                                                 NoOwnerWarning, no_owner_text)
from rbx1_nav.sim_time.member_inputs_ros import CountedInputs, connected_publishers
from rbx1_nav.sim_time.member_join_ros import JoinError, Joining
from rbx1_nav.sim_time.member_reports_ros import REPORT_TOPIC, CountedPublisher, Reports

__all__ = ['GRANT_TOPIC', 'REPORT_TOPIC', 'GRANT_LIMIT', 'POLL', 'STALLED',
           'NO_OWNER_WARNING', 'NO_OWNER_REMINDER', 'no_owner_text', 'NoOwnerWarning',
           'connected_publishers', 'JoinError',
           'Member', 'CountedPublisher']


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
        self.follower = Follower()
        # One condition for the grants and the inputs: an arrival or a
        # grant wakes every wait of the member.
        cond = threading.Condition()
        self.reports = Reports(self.follower, every_step, passive)
        self.inputs = CountedInputs(self.name, cond, self.reports, inputs, hold)
        # After the parts its grants reach: it subscribes, and a grant may
        # come at once.
        self.receiver = GrantReceiver(self.name, cond, self.follower, self.reports,
                                      self.inputs, step)
        self.joining = Joining(self.name, self.reports, self.receiver, self.inputs)

    # Joining (Joining)
    def join(self, wait):
        return self.joining.join(wait)

    def join_patiently(self, log_name):
        return self.joining.join_patiently(log_name)

    def wait_for_inputs(self, limit, log_name):
        return self.joining.wait_for_inputs(limit, log_name)

    # The grants (GrantReceiver)
    def wait_grant(self, limit=None):
        return self.receiver.wait_grant(limit)

    def grants(self, log_name):
        return self.receiver.grants(log_name)

    def serve(self, warning):
        return self.receiver.serve(warning)

    def simulators(self):
        return self.receiver.simulators()

    # Messages in (CountedInputs)
    def arrived(self, topic, msg, item=None):
        return self.inputs.arrived(topic, msg, item)

    def take(self, grant, key, topic=None):
        return self.inputs.take(grant, key, topic)

    def wait_counted(self, grant):
        return self.inputs.wait_counted(grant)

    # Messages out and the reports (Reports)
    def sent(self, topic):
        return self.reports.sent(topic)

    def publisher(self, topic, msg_class):
        return self.reports.publisher(topic, msg_class)

    def report(self, handled_ns, next_ns, leaving=False):
        return self.reports.report(handled_ns, next_ns, leaving)

    def leave(self):
        return self.reports.leave()
