"""A course node's clock and link to the robot under lockstep simulated
time: the variants of rbx1_nav.motion.runner.clock_ros.RateClock and
rbx1_nav.motion.runner.robot_link_ros.RobotLink that the runner is handed when the
graph steps with its nodes (rbx1_nav.entry.course_clock_ros).

The node is a member from its wait for the transform to the end of its
course: it joins the owner of simulated time, waits for each grant naming
it (the simulator has published its state at that tick), handles the
tick, and reports it handled with its next tick 1/~rate s on; time waits
for it. Its first tick is the first multiple of 0.1 s of simulated time
(rbx1_nav.sim_time.member.ALIGN) after the step it joined at, so it meets
the simulator's steps at the same offsets and ends the same whenever it
started. A node that drives several courses in a row (UMBmark's runs)
stays a member between them: time then waits for it between courses too,
so each course starts at the same simulated time on every run.

What the course reads is what the grant of its tick counts, the same on
every run: the /tf and odometry messages are held until a grant counts
them; following a simulator's transform, the state stamped at the very
tick (waited for in wall time, woken by each /tf message); following
another member's (a filter's, whose stamps are not ticks), the last of
its messages the grant counts, whatever came after. Each command is on
its way before the tick's report (a synchronous publisher), and counted,
so the simulator steps on only once it has them all.
"""
import threading
import time

import rospy
import yaml

from rbx1_nav.common.aborted import CourseAborted
from rbx1_nav.common.publish_ros import from_ns, synchronous_publisher, to_ns
from rbx1_nav.common.rospy_private_ros import sender
from rbx1_nav.sim_time import member_ros as lockstep
from rbx1_nav.sim_time.clock_watch_ros import require_clock
from rbx1_nav.sim_time.member import BACK, aligned


def member_clock(rate, wait, timeout, stop, tf_topic, odom_topic):
    """(clock, link) of a course that is a member at ``rate`` Hz;
    ``tf_topic`` and ``odom_topic`` (resolved) are the inputs held for the
    grants (the rest: :class:`MemberClock`)."""
    clock = MemberClock(rate, wait, timeout, stop,
                        lockstep.Member(inputs=[tf_topic, odom_topic], hold=True))
    return clock, MemberLink(clock, tf_topic)


class MemberClock(object):
    """The ticks at ``rate`` Hz granted to this node, a ``member``. Before
    the join, the wait for the inputs' connections and the join itself
    each wait up to ``wait`` wall s (~tf_wait); a grant is waited for as
    long as the owner is connected, and up to max(GRANT_LIMIT,
    ``timeout``) wall s (~tf_timeout) after the last tick once it is not
    (the first of a membership, up to ``wait`` too); ``stop()`` stops the
    robot when the owner is gone. ``joined()``, once set, runs on each
    join (the link's look at who broadcasts the robot's transform)."""

    def __init__(self, rate, wait, timeout, stop, member):
        self.rate = rate
        self.wait = wait
        self.timeout = timeout
        self.stop = stop
        self.member = member
        self.grant = None  # the grant of the current tick
        self.unreported = None  # a tick handed out and not reported (ns)
        self.joined = lambda: None

    def start(self, name):
        """Before the first course: the first /clock awaited (a stopped one
        needs no watch: the grants have a limit of their own)."""
        require_clock(self.wait)

    def ticks(self):
        """The granted control ticks (ROS times); the caller ends the
        membership with :meth:`leave`."""
        member = self.member
        period = int(round(1e9 / self.rate))
        limit = max(lockstep.GRANT_LIMIT, self.timeout)
        wait = limit
        joining = False  # the next grant is a new membership's first
        first = None  # the first tick of a new membership (ns)
        if self.unreported is not None:  # still a member: the next tick
            member.report(self.unreported, self.unreported + period)
            self.unreported = None
        else:
            # The first grant may wait for the other members sim_clock's
            # ~members counts: up to the start-up wait (~tf_wait).
            wait = max(limit, self.wait)
            member.wait_for_inputs(self.wait, member.name)
            try:
                member.join(self.wait)
            except lockstep.JoinError as err:
                raise CourseAborted('/lockstep is set but this node cannot join: %s. '
                                    'Start the simulator with lockstep too, or set '
                                    '/lockstep false' % err)
            self.joined()
            joining = True
        while True:
            granted = member.wait_grant(wait)
            if granted is None:
                if rospy.is_shutdown():
                    return
                self.stop()
                raise CourseAborted(
                    '/clock has not advanced: nothing has granted lockstep steps on '
                    '%s for %.1f s of wall time (sim_clock gone); stopped the robot'
                    % (lockstep.GRANT_TOPIC, wait))
            wait = limit
            action, tick, grant = granted
            self.grant = grant
            if action == BACK:
                raise rospy.ROSTimeMovedBackwardsException(
                    (member.follower.handled - tick) * 1e-9)
            if joining:
                # The join grant is not a tick. From it on, every message a
                # grant counts on this node's inputs is awaited
                # (MessageLedger.settle); one sent just before the join may
                # have come or not, so the first tick comes after it: a
                # course then finds its robot and starts at the same tick
                # on every run.
                member.wait_counted(grant)
                first, joining = aligned(tick + 1), False
            if first is not None and tick < first:
                member.report(tick, first)  # not a tick of this node's
                continue
            first = None
            self.unreported = tick
            yield from_ns(tick)
            self.unreported = None
            member.report(tick, tick + period)

    def pause(self, seconds):
        """Wait ``seconds`` of ROS time: as granted ticks while a member
        between courses (time waits for this node), else rospy.sleep."""
        if self.unreported is None:
            rospy.sleep(seconds)
            return
        end = None
        for now in self.ticks():
            if end is None:
                end = now + rospy.Duration.from_sec(seconds)
            if now >= end:
                return

    def leave(self):
        """Leave the lockstep after the last course."""
        self.unreported = None
        self.member.leave()


class MemberLink(object):
    """The course's link to the robot as a member of ``clock`` (a
    :class:`MemberClock`): ``tf_topic`` (resolved) and odometry held for
    the grants that count them, each command counted."""

    counts_commands = True

    def __init__(self, clock, tf_topic):
        self.clock = clock
        self.member = clock.member
        self.tf_topic = tf_topic
        self.tf = None  # the course's rbx1_nav.motion.runner.tf_follow_ros.TfFollower
        self.tf_came = threading.Condition()
        # The node broadcasting the followed transform, whether it is a
        # simulator, and the stamp (ns) of the last transform of the
        # broadcaster that a grant counted.
        self.broadcaster = self.simulator = self.counted = None
        # (sender, child frame) -> the newest stamp (ns) a grant counted of
        # it; child frame -> the newest stamp (ns) heard.
        self.seen = {}
        self.heard = {}
        clock.joined = lambda: self._pick(self.tf and self.tf.followed)

    def arrived(self, topic, msg, item):
        """Count each input message and hold ``item`` until a grant counts
        it; of /tf, note the stamps of its frames (``item`` is the
        message)."""
        if topic == self.tf_topic:
            frames, heard = {}, self.heard
            for t in msg.transforms:
                child = t.child_frame_id.lstrip('/')
                frames[child] = max(to_ns(t.header.stamp), frames.get(child, 0))
                heard[child] = max(frames[child], heard.get(child, 0))
            item = (sender(msg), frames)
        self.member.arrived(topic, msg, item)
        if topic == self.tf_topic:
            with self.tf_came:
                self.tf_came.notify_all()
        return True

    def take(self, topic, key):
        """The items the current tick's grant counts on ``topic``."""
        if self.clock.grant is None:
            return ()
        return self.member.take(self.clock.grant, key=key, topic=topic)

    def publisher(self, topic, msg_class, headers=None):
        """Each command written before publish() returns."""
        return synchronous_publisher(topic, msg_class, headers=headers)

    def sent(self, topic):
        self.member.sent(topic)

    def takers(self, nodes):
        """The simulators among ``nodes``: a simulator that takes part
        counts every command, so none may go out before its connection
        is up."""
        return set(nodes) & self.member.simulators()

    def not_taken(self, topic, nodes, wait):
        return ('/lockstep is set but the node taking %s (%s) is not granted '
                'lockstep steps on %s after %.1f s: start the simulator with '
                'lockstep too, or set /lockstep false'
                % (topic, ', '.join(sorted(nodes)), lockstep.GRANT_TOPIC, wait))

    def looks(self, tf, deadline):
        """At each tick granted while the course waits for its transform:
        the base frame found, or None; the same tick on every run (the
        start-up wait, ``deadline``, counts wall seconds)."""
        self.tf = tf
        for _ in self.clock.ticks():
            frame = self._found_at(tf)
            if frame is not None:
                self._pick(frame)
            yield frame

    def _take_tf(self):
        """Note the /tf messages the current grant counts."""
        for who, frames in self.take(self.tf_topic, key=lambda item: 0):
            for child, stamp in frames.items():
                key = (who, child)
                self.seen[key] = max(stamp, self.seen.get(key, 0))

    def _found_at(self, tf):
        """A candidate counts once tf has it and, if its broadcaster takes
        part in lockstep (a simulator, a filter: each counts its /tf
        messages), once a message of it is among those the grant counts;
        one from a node outside lockstep counts as it comes."""
        self._take_tf()
        grant = self.clock.grant
        members = set(grant.members) | {
            who for topic, who in zip(grant.topics, grant.senders)
            if topic == self.tf_topic}
        for frame in tf.candidates():
            if tf.has(frame):
                who = self._broadcaster(frame)
                if who not in members or (who, frame) in self.seen:
                    return frame
        return None

    def _broadcaster(self, frame):
        """The node that sent ``frame``'s transform to the tf buffer."""
        frames = yaml.safe_load(self.tf.buffer.all_frames_as_yaml()) or {}
        return frames.get(frame, {}).get('broadcaster')

    def _pick(self, followed):
        """On joining, and once the followed frame is found: who
        broadcasts it, and whether it is one of the simulators (a
        filter's transform has stamps that are not steps)."""
        self.simulator = self.broadcaster = None
        if not followed:
            return
        self.broadcaster = self._broadcaster(followed)
        if self.broadcaster in self.member.simulators():
            self.simulator = self.broadcaster

    def reading(self, tf, now):
        """Following the transform of a simulator granted the same tick,
        first wait for its state at that very time (it publishes it on
        the same grant), however long that takes while the simulator is
        connected (up to STALLED s, a backstop); if it is not (it died),
        take what there is: the staleness check then ends the course.
        Following another member's transform (a filter's), take the last
        one the grant counts (waiting for it, as a simulator waits for its
        commands), not one published since."""
        self.tf = tf
        self._take_tf()
        grant = self.clock.grant
        counted = self.seen.get((self.broadcaster, tf.followed))
        if counted is not None:
            self.counted = counted
        if self.simulator is not None:
            if self.simulator in grant.members:
                tick = to_ns(now)
                stalled = time.monotonic() + lockstep.STALLED

                # The lookup only once the followed transform itself has
                # come that far (a message on /tf wakes this each time).
                def there():
                    if self.heard.get(tf.followed, 0) < tick:
                        return False
                    reading = tf.lookup()
                    return reading is not None and to_ns(reading[1]) >= tick
                while not (self._wait_tf(there)
                           or self.simulator not in lockstep.connected_publishers(
                               self.tf_topic)
                           or time.monotonic() > stalled or rospy.is_shutdown()):
                    pass
        elif self.counted is not None and self.broadcaster in grant.senders:
            return tf.lookup(rospy.Time(nsecs=self.counted))
        return tf.lookup()

    def _wait_tf(self, ready):
        """Wait up to POLL wall s until ``ready()``; its result."""
        with self.tf_came:
            return self.tf_came.wait_for(ready, lockstep.POLL)
