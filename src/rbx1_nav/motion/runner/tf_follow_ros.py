"""Following the robot on tf (odom -> base); each /tf message also goes to the link (RobotLink.arrived).

An invalid odom -> base transform (NaN, or a rotation that is not a unit quaternion) never
reaches the tf buffer, where tf2 would drop it anyway, logging an error for each one: the
follower notes who sent it, so "no transform" and "invalid transforms" read differently."""
import threading

import rospy
import tf2_ros

from rbx1_nav.common.aborted import CourseAborted
from rbx1_nav.common.rospy_private_ros import sender
from rbx1_nav.motion.runner.deadline_ros import Deadline
from rbx1_nav.motion.runner.invalid_poses import InvalidPoses, no_transform_text, pose_problem
from rbx1_nav.transform_utils import Pose2D, quat_to_angle

BASE_FRAME_CANDIDATES = ('base_footprint', 'base_link')
#: The tf topic, as tf2_ros's listener names it (so a remap of /tf applies).
TF_TOPIC = '/tf'


class _Listener(tf2_ros.TransformListener):
    """tf2 listener (without Nagle's delay) passing on each /tf message once the buffer has it;
    ``screen(msg)``: the message's invalid transforms to keep from the buffer, [(transform,
    problem)]; ``on_message(msg, invalid)`` is given them."""

    def __init__(self, buffer, screen, on_message):
        self.screen = screen
        self.on_message = on_message
        super(_Listener, self).__init__(buffer, tcp_nodelay=True)

    def callback(self, data):
        invalid = self.screen(data)
        if invalid:
            # The message is rospy's one copy for every callback on /tf: put it back as it was.
            every, skip = data.transforms, {id(t) for t, _ in invalid}
            data.transforms = [t for t in every if id(t) not in skip]
            try:
                super(_Listener, self).callback(data)
            finally:
                data.transforms = every
        else:
            super(_Listener, self).callback(data)
        self.on_message(data, invalid)


class TfFollower(object):
    """The transform ``odom_frame -> base_frame`` steered by; ``link``: the course's (a RobotLink)."""

    def __init__(self, name, odom_frame, base_frame, link):
        self.name = name
        self.odom_frame = odom_frame
        self.base_frame = base_frame  # '' = automatic
        self.followed = None  # the base frame found on tf
        self.link = link
        self.tf_topic = rospy.resolve_name(TF_TOPIC)
        self.guard = None  # while a course runs: its TransformGuard
        self.lock = threading.Lock()
        self.invalid = {}  # base frame -> InvalidPoses of odom -> it, since the wait began
        self.buffer = tf2_ros.Buffer()
        self.listener = _Listener(self.buffer, self._screen, self._on_tf)

    def _screen(self, msg):
        """[(transform, problem)] of the invalid odom -> base transforms in ``msg``."""
        invalid = []
        candidates = self.candidates()
        for t in msg.transforms:
            if (t.child_frame_id.lstrip('/') in candidates
                    and t.header.frame_id.lstrip('/') == self.odom_frame):
                v, q = t.transform.translation, t.transform.rotation
                problem = pose_problem((v.x, v.y, v.z), (q.x, q.y, q.z, q.w))
                if problem is not None:
                    invalid.append((t, problem))
        return invalid

    def _on_tf(self, msg, invalid):
        """Each update of the followed transform to ``guard`` (an invalid one as such), the
        invalid ones to ``invalid``, every message to the link."""
        guard = self.guard  # read once: run() clears it from another thread
        if invalid:
            node = sender(msg)
            with self.lock:
                for t, problem in invalid:
                    child = t.child_frame_id.lstrip('/')
                    self.invalid.setdefault(child, InvalidPoses()).heard(node, problem)
                    if guard is not None and child == self.followed:
                        guard.invalid(node, problem)
        if guard is not None:
            skip = {id(t) for t, _ in invalid}
            for t in msg.transforms:
                if t.child_frame_id.lstrip('/') == self.followed and id(t) not in skip:
                    v = t.transform.translation
                    guard.heard(sender(msg), t.header.stamp.to_sec(), v.x, v.y,
                                quat_to_angle(t.transform.rotation))
        self.link.arrived(self.tf_topic, msg, msg)

    def find_base_frame(self, wait, require_tf):
        """Wait up to ``wait`` wall s for odom -> base; return the base frame found, else None
        (blind) or, with ``require_tf``, CourseAborted."""
        candidates = self.candidates()
        rospy.loginfo('Waiting up to %.1f s for tf %s -> %s', wait,
                      self.odom_frame, ' or '.join(candidates))
        deadline = Deadline(wait)
        with self.lock:
            self.invalid = {}
        for frame in self.link.looks(self, deadline):
            if frame is not None:
                rospy.loginfo('Following tf %s -> %s', self.odom_frame, frame)
                return frame
            if deadline.expired() or rospy.is_shutdown():
                break
        if rospy.is_shutdown():
            raise rospy.ROSInterruptException('shutdown while waiting for tf')
        with self.lock:
            problem, fix = no_transform_text(self.odom_frame, candidates, wait, self.invalid)
        if not require_tf:
            rospy.logwarn('%s: %s; running the course open loop without a '
                          'position report', self.name, problem)
            return None
        raise CourseAborted('%s. %s' % (problem, fix))

    def polls(self, deadline):
        """The first candidate tf has, or None, every 1/20 wall s."""
        while True:
            yield next((frame for frame in self.candidates() if self.has(frame)), None)
            deadline.poll(20)

    def has(self, frame):
        """True when tf has odom_frame -> ``frame``."""
        return self.buffer.can_transform(self.odom_frame, frame, rospy.Time(0))

    def candidates(self):
        """The base frames to look for: ~base_frame, or the usual ones."""
        return (self.base_frame,) if self.base_frame else BASE_FRAME_CANDIDATES

    def lookup(self, stamp=None):
        """(Pose2D, stamp) of odom -> base at ``stamp`` (None: the latest), or None."""
        try:
            tf = self.buffer.lookup_transform(self.odom_frame, self.followed,
                                              stamp or rospy.Time(0))
        except tf2_ros.TransformException:
            return None
        t, q = tf.transform.translation, tf.transform.rotation
        return Pose2D(t.x, t.y, quat_to_angle(q)), tf.header.stamp
