"""Following the robot on tf (odom -> base); each /tf message also goes to Ticks.arrived."""
import rospy
import tf2_ros

from rbx1_nav.common.aborted import CourseAborted
from rbx1_nav.common.rospy_private_ros import sender
from rbx1_nav.motion.deadline_ros import Deadline
from rbx1_nav.transform_utils import Pose2D, quat_to_angle

BASE_FRAME_CANDIDATES = ('base_footprint', 'base_link')
#: The tf topic, as tf2_ros's listener names it (so a remap of /tf applies).
TF_TOPIC = '/tf'


class _Listener(tf2_ros.TransformListener):
    """tf2 listener (without Nagle's delay) passing on each /tf message once the buffer has it."""

    def __init__(self, buffer, on_message):
        self.on_message = on_message
        super(_Listener, self).__init__(buffer, tcp_nodelay=True)

    def callback(self, data):
        super(_Listener, self).callback(data)
        self.on_message(data)


class TfFollower(object):
    """The transform ``odom_frame -> base_frame`` steered by; ``clock``: the course's (a Ticks)."""

    def __init__(self, name, odom_frame, base_frame, clock):
        self.name = name
        self.odom_frame = odom_frame
        self.base_frame = base_frame  # '' = automatic
        self.followed = None  # the base frame found on tf
        self.clock = clock
        self.tf_topic = rospy.resolve_name(TF_TOPIC)
        self.guard = None  # while a course runs: its TransformGuard
        self.buffer = tf2_ros.Buffer()
        self.listener = _Listener(self.buffer, self._on_tf)

    def _on_tf(self, msg):
        """Each update of the followed transform to ``guard``, every message to the clock."""
        guard = self.guard  # read once: run() clears it from another thread
        if guard is not None:
            for t in msg.transforms:
                if t.child_frame_id.lstrip('/') == self.followed:
                    v = t.transform.translation
                    guard.heard(sender(msg), t.header.stamp.to_sec(), v.x, v.y,
                                quat_to_angle(t.transform.rotation))
        self.clock.arrived(self.tf_topic, msg, msg)

    def find_base_frame(self, wait, require_tf):
        """Wait up to ``wait`` wall s for odom -> base; return the base frame found, else None
        (blind) or, with ``require_tf``, CourseAborted."""
        candidates = self.candidates()
        rospy.loginfo('Waiting up to %.1f s for tf %s -> %s', wait,
                      self.odom_frame, ' or '.join(candidates))
        deadline = Deadline(wait)
        for frame in self.clock.looks(self, deadline):
            if frame is not None:
                rospy.loginfo('Following tf %s -> %s', self.odom_frame, frame)
                return frame
            if deadline.expired() or rospy.is_shutdown():
                break
        if rospy.is_shutdown():
            raise rospy.ROSInterruptException('shutdown while waiting for tf')
        problem = ('no transform from %s to %s after %.1f s: nothing is publishing the robot\'s '
                   'odometry on tf' % (self.odom_frame, ' or '.join(candidates), wait))
        if not require_tf:
            rospy.logwarn('%s: %s; running the course open loop without a '
                          'position report', self.name, problem)
            return None
        raise CourseAborted(
            '%s. Start the robot first: roslaunch rbx1_nav fake_turtlebot.launch for the '
            'simulator, or the robot\'s driver (e.g. its bringup launch) on a real robot; or set '
            '~odom_frame / ~base_frame to the frames your robot uses.' % problem)

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
