"""Following the robot on tf: odom_frame -> base_frame, for the runner.

:class:`TfFollower` finds the base frame (~base_frame, or the first of
base_footprint and base_link that tf has), looks up the latest transform
as a Pose2D, and under lockstep reads the state at a tick: a
simulator's, stamped at that very tick (it waits, in wall time, woken by
each /tf message rather than polling), or another member's (a filter's,
whose stamps are not ticks): the transform of the last of its messages
the grant counts, whatever came after (the same on every run).
"""
import threading
import time

import rospy
import tf2_ros
import yaml

from rbx1_nav.common import lockstep_member_ros as lockstep
from rbx1_nav.common.publish_ros import sender, to_ns
from rbx1_nav.motion.aborted import CourseAborted
from rbx1_nav.motion.deadline_ros import Deadline
from rbx1_nav.transform_utils import Pose2D, quat_to_angle

BASE_FRAME_CANDIDATES = ('base_footprint', 'base_link')
#: The tf topic, as tf2_ros's listener names it (so a remap of /tf applies).
TF_TOPIC = '/tf'


class _Listener(tf2_ros.TransformListener):
    """tf2 listener that wakes :meth:`wait` on every /tf message, over
    connections without Nagle's delay."""

    def __init__(self, buffer, on_message):
        self.cond = threading.Condition()
        self.on_message = on_message
        super(_Listener, self).__init__(buffer, tcp_nodelay=True)

    def callback(self, data):
        super(_Listener, self).callback(data)
        self.on_message(data)
        with self.cond:
            self.cond.notify_all()

    def wait(self, ready, timeout):
        """Wait up to ``timeout`` wall seconds until ``ready()``; its result."""
        with self.cond:
            return self.cond.wait_for(ready, timeout)


class TfFollower(object):
    """The transform ``odom_frame -> base_frame`` ('' = automatic) the
    node steers by; ``name`` is the node's, for its warnings; ``member``
    its lockstep membership (None off lockstep), made with the resolved
    /tf topic (:data:`TF_TOPIC`) as input, ``hold`` true."""

    def __init__(self, name, odom_frame, base_frame, member=None):
        self.name = name
        self.odom_frame = odom_frame
        self.base_frame = base_frame  # '' = automatic
        self.followed = None  # the base frame found on tf
        self.member = member
        self.tf_topic = rospy.resolve_name(TF_TOPIC)
        # While a course runs: its rbx1_nav.motion.tf_guard.TransformGuard.
        self.guard = None
        self.buffer = tf2_ros.Buffer()
        self.listener = _Listener(self.buffer, self._on_tf)
        # Lockstep: the node broadcasting the followed transform, whether
        # it is a simulator, how long (wall s) to wait for a simulator's
        # state at a tick, and the stamp (ns) of the last transform of
        # the broadcaster that a grant counted.
        self.broadcaster = None
        self.simulator = None
        self.counted = None
        # Lockstep: (sender, child frame) -> the newest stamp (ns) a grant
        # counted of it; child frame -> the newest stamp (ns) heard.
        self.seen = {}
        self.heard = {}

    def _on_tf(self, msg):
        """Feed each update of the followed transform to ``guard`` (while a
        course runs); under lockstep, count each /tf message, keeping
        (sender, stamp ns of the followed transform in it or None) until a
        grant counts it."""
        followed = [t for t in msg.transforms
                    if t.child_frame_id.lstrip('/') == self.followed]
        guard = self.guard
        if guard is not None:
            for t in followed:
                v = t.transform.translation
                guard.heard(sender(msg), t.header.stamp.to_sec(), v.x, v.y,
                            quat_to_angle(t.transform.rotation))
        if self.member is None:
            return
        frames, heard = {}, self.heard
        for t in msg.transforms:
            child = t.child_frame_id.lstrip('/')
            frames[child] = max(to_ns(t.header.stamp), frames.get(child, 0))
            heard[child] = max(frames[child], heard.get(child, 0))
        self.member.arrived(self.tf_topic, msg, (sender(msg), frames))

    def find_base_frame(self, wait, require_tf, ticks=None):
        """Wait up to ``wait`` wall s for odom -> base; return the base
        frame, or None when ``require_tf`` is false (the course runs
        blind); CourseAborted when it is true. Under lockstep ``ticks``
        yields the grant of each tick granted meanwhile: the frame is found
        at a tick (:meth:`found_at`), the same on every run."""
        candidates = self.candidates()
        rospy.loginfo('Waiting up to %.1f s for tf %s -> %s', wait,
                      self.odom_frame, ' or '.join(candidates))
        deadline = Deadline(wait, True)
        looks = (self._polls(candidates, deadline) if ticks is None else
                 (self.found_at(grant) for grant in ticks))
        for frame in looks:
            if frame is not None:
                rospy.loginfo('Following tf %s -> %s', self.odom_frame, frame)
                return frame
            if deadline.expired() or rospy.is_shutdown():
                break
        if rospy.is_shutdown():
            raise rospy.ROSInterruptException('shutdown while waiting for tf')
        problem = (
            'no transform from %s to %s after %.1f s: nothing is publishing '
            'the robot\'s odometry on tf' % (self.odom_frame,
                                             ' or '.join(candidates), wait))
        if not require_tf:
            rospy.logwarn('%s: %s; running the course open loop without a '
                          'position report', self.name, problem)
            return None
        raise CourseAborted(
            '%s. Start the robot first: roslaunch rbx1_nav fake_turtlebot.launch '
            'for the simulator, or the robot\'s driver (e.g. its bringup '
            'launch) on a real robot; or set ~odom_frame / ~base_frame to the '
            'frames your robot uses.' % problem)

    def _polls(self, candidates, deadline):
        """The first of ``candidates`` tf has, or None, every 1/20 wall s."""
        while True:
            yield next((frame for frame in candidates if self.buffer.can_transform(
                self.odom_frame, frame, rospy.Time(0))), None)
            deadline.poll(20)

    def _take(self, grant):
        """Note the /tf messages ``grant`` counts (held until it does)."""
        for who, frames in self.member.take(grant, key=lambda item: 0,
                                            topic=self.tf_topic):
            for child, stamp in frames.items():
                key = (who, child)
                self.seen[key] = max(stamp, self.seen.get(key, 0))

    def found_at(self, grant):
        """Under lockstep, at a start-up tick (``grant``): the base frame
        found, or None; the same tick on every run.

        A candidate counts once tf has it and, if its broadcaster takes
        part in lockstep (a simulator, a filter: each counts its /tf
        messages), once a message of it is among those the grant counts;
        one from a node outside lockstep counts as it comes.
        """
        self._take(grant)
        members = set(grant.members) | {
            who for topic, who in zip(grant.topics, grant.senders)
            if topic == self.tf_topic}
        for frame in self.candidates():
            if self.buffer.can_transform(self.odom_frame, frame, rospy.Time(0)):
                who = self._broadcaster(frame)
                if who not in members or (who, frame) in self.seen:
                    return frame
        return None

    def candidates(self):
        """The base frames to look for: ~base_frame, or the usual ones."""
        return (self.base_frame,) if self.base_frame else BASE_FRAME_CANDIDATES

    def _broadcaster(self, frame):
        """The node that sent ``frame``'s transform to the tf buffer."""
        frames = yaml.safe_load(self.buffer.all_frames_as_yaml()) or {}
        return frames.get(frame, {}).get('broadcaster')

    def lookup(self, stamp=None):
        """(Pose2D, stamp) of the odom -> base transform at ``stamp`` (None:
        the latest), or None."""
        try:
            tf = self.buffer.lookup_transform(self.odom_frame, self.followed,
                                              stamp or rospy.Time(0))
        except tf2_ros.TransformException:
            return None
        t, q = tf.transform.translation, tf.transform.rotation
        return Pose2D(t.x, t.y, quat_to_angle(q)), tf.header.stamp

    def pick_simulator(self, simulators):
        """Under lockstep, on joining: note who broadcasts the followed
        transform, and whether it is one of the ``simulators`` (a
        filter's transform has stamps that are not steps). None when
        blind (no transform followed)."""
        self.simulator = self.broadcaster = None
        if self.followed is None:
            return
        self.broadcaster = self._broadcaster(self.followed)
        if self.broadcaster in simulators:
            self.simulator = self.broadcaster

    def reading(self, now, grant):
        """(pose, stamp) for the tick at ``now``, or None; ``grant`` the
        lockstep grant of that tick (None off lockstep).

        Under lockstep, following the transform of a simulator granted the
        same tick, first wait for its state at that very time (it
        publishes it on the same grant), however long that takes while
        the simulator is connected (up to STALLED s, a backstop); if it is
        not (it died), take what there is: the staleness check then ends
        the course. Following another member's transform (a filter's),
        take the last one the grant counts (waiting for it, as a simulator
        waits for its commands), not one published since.
        """
        if grant is None:
            return self.lookup()
        self._take(grant)
        counted = self.seen.get((self.broadcaster, self.followed))
        if counted is not None:
            self.counted = counted
        if self.simulator is not None:
            if self.simulator in grant.members:
                tick = to_ns(now)
                topic = self.listener.tf_sub.resolved_name
                stalled = time.monotonic() + lockstep.STALLED

                # The lookup only once the followed transform itself has
                # come that far (a message on /tf wakes this each time).
                def there():
                    return self.heard.get(self.followed, 0) >= tick and self._stamp() >= tick
                while not (self.listener.wait(there, lockstep.POLL)
                           or self.simulator not in lockstep.connected_publishers(topic)
                           or time.monotonic() > stalled or rospy.is_shutdown()):
                    pass
        elif self.counted is not None and self.broadcaster in grant.senders:
            return self.lookup(rospy.Time(nsecs=self.counted))
        return self.lookup()

    def _stamp(self):
        """Stamp (ns) of the latest transform followed; 0 if none."""
        reading = self.lookup()
        return 0 if reading is None else to_ns(reading[1])
