"""A lockstep member's grants: each step the owner grants to this node,
received, waited for and handled (a part of
rbx1_nav.sim_time.member_ros.Member; what to do with each grant:
rbx1_nav.sim_time.member.Follower).
"""
import time

import rospy

from rbx1_nav.sim_time.member import (LOST_MESSAGES, POLL, REPEAT, RESEND, STALE,
                                      Reminder)
from rbx1_nav.common.publish_ros import keep_own_time, to_ns
from rbx1_nav.common.rospy_private_ros import set_rostime
from rbx1_nav.msg import LockstepGrant

#: A global topic, like /clock: one owner of simulated time per master.
GRANT_TOPIC = '/lockstep_grant'
#: Wall seconds after its last step a motion node takes the clock as gone
#: if no owner is connected (sim_clock gone; a new one may take over
#: meanwhile). While the owner is connected it waits however
#: long time takes: time waits for the slowest member (sim_clock names it
#: every second), and a loaded machine only makes a step take longer.
GRANT_LIMIT = 4.0
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


class GrantReceiver(object):
    """The grants on GRANT_TOPIC, from the moment it is made. A member
    waits for each granted to it with :meth:`wait_grant` (or
    :meth:`grants`); a simulator (``step`` given: see
    rbx1_nav.sim_time.member_ros.Member) has each handled in the thread
    that receives it, while :meth:`serve` keeps its reports going.
    ``cond`` is the member's condition, shared with its ``inputs`` (a
    CountedInputs); ``reports`` (a Reports) answers each step."""

    def __init__(self, name, cond, follower, reports, inputs, step):
        self.name = name
        self.cond = cond
        self.follower = follower
        self.reports = reports
        self.inputs = inputs
        self.step = step
        self.busy = False       # a step being handled (serve)
        self.heard = None       # wall time of the last grant or step handled
        self.failure = None     # what step raised, for serve to raise
        self.grant = None       # the newest grant naming this node
        self.members = set()    # the names in the newest grant seen
        self.sims = set()       # the simulators it names
        self.rejoin = False     # a new owner is there: send the report now
        self.own_time = False   # ROS time set from the grants (a simulator)
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
            elif self.reports.joined and msg.session != self.follower.session:
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
                if self.inputs.inbox is None:
                    self.inputs.wait_counted(grant)
                    held = []
                else:  # a simulator's commands: per sender, as they came
                    held = self.inputs.take(grant, key=lambda item: 0)
                self.reports.report(time_ns, self.step(action, time_ns, held))
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
        (``warning``, a NoOwnerWarning) while it gets none. A shutdown wakes
        it: a node roslaunch ends exits at once."""
        rospy.on_shutdown(self._wake)
        ending = rospy.core.is_shutdown_requested
        while not ending():
            with self.cond:
                self.cond.wait_for(
                    lambda: self.rejoin or self.failure is not None or ending(), RESEND)
                if self.failure is not None:
                    raise self.failure
                rejoin, self.rejoin = self.rejoin, False
                now = time.monotonic()
                quiet = not self.busy and now - self.heard > RESEND
            if rejoin or quiet:
                self.reports.send_again()
            if quiet:
                warning.check()
            else:
                warning.granted()
        deadline = time.monotonic() + LOST_MESSAGES
        while self.busy and time.monotonic() < deadline:  # a step under way ends
            rospy.rostime.wallsleep(0.01)                  # before the node does

    def _wake(self):
        with self.cond:
            self.cond.notify_all()

    def simulators(self):
        """The simulators taking part, as the newest grant names them."""
        with self.cond:
            return set(self.sims)

    def named(self):
        """The members, as the newest grant names them."""
        with self.cond:
            return set(self.members)

    def restart(self):
        """On joining: a grant received before is not awaited, and the wait
        for the first one starts now."""
        with self.cond:
            self.grant = None
            self.heard = time.monotonic()

    def take_own_time(self):
        """A simulator's ROS time from now on: the grants' (keep_own_time)."""
        if not self.own_time:
            self.own_time = keep_own_time()

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
                    self.reports.send_again()
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
            self.reports.send_again()
        elif action == STALE:
            rospy.logwarn('%s: lockstep grant at %.3f s is before the step '
                          'already handled (%.3f s): refused', self.name,
                          time_ns * 1e-9, self.follower.handled * 1e-9)
        else:
            if self.own_time:
                set_rostime(grant.time)
            return action, time_ns, grant
        return None
