"""Following the robot on tf: odom_frame -> base_frame, for the runner.

:class:`TfFollower` finds the base frame (~base_frame, or the first of
base_footprint and base_link that tf has), looks up the latest transform
as a Pose2D, and under lockstep reads the simulator's state at a tick:
it waits (wall time) for the transform stamped at that tick, woken by
each /tf message rather than polling.
"""
import threading

import rospy
import tf2_ros
import yaml

from rbx1_nav.common import lockstep_member_ros as lockstep
from rbx1_nav.common.publish_ros import to_ns
from rbx1_nav.motion.aborted import CourseAborted
from rbx1_nav.motion.deadline_ros import Deadline
from rbx1_nav.transform_utils import Pose2D, quat_to_angle

BASE_FRAME_CANDIDATES = ('base_footprint', 'base_link')


class _Listener(tf2_ros.TransformListener):
    """tf2 listener that wakes :meth:`wait` on every /tf message, over
    connections without Nagle's delay."""

    def __init__(self, buffer):
        self.cond = threading.Condition()
        super(_Listener, self).__init__(buffer, tcp_nodelay=True)

    def callback(self, data):
        super(_Listener, self).callback(data)
        with self.cond:
            self.cond.notify_all()

    def wait(self, ready, timeout):
        """Wait up to ``timeout`` wall seconds until ``ready()``; its result."""
        with self.cond:
            return self.cond.wait_for(ready, timeout)


class TfFollower(object):
    """The transform ``odom_frame -> base_frame`` ('' = automatic) the
    node steers by; ``name`` is the node's, for its warnings."""

    def __init__(self, name, odom_frame, base_frame):
        self.name = name
        self.odom_frame = odom_frame
        self.base_frame = base_frame  # '' = automatic
        self.followed = None  # the base frame found on tf
        self.buffer = tf2_ros.Buffer()
        self.listener = _Listener(self.buffer)
        # Lockstep: the simulator whose transform is followed (None: not
        # a simulator's), and how long (wall s) to wait for its state at
        # a tick.
        self.simulator = None
        self.state_wait = lockstep.STATE_LIMIT

    def find_base_frame(self, wait, wall, require_tf):
        """Wait up to ``wait`` s (wall s when ``wall``) for odom -> base;
        return the base frame, or None when ``require_tf`` is false (the
        course runs blind); CourseAborted when it is true."""
        candidates = ((self.base_frame,) if self.base_frame
                      else BASE_FRAME_CANDIDATES)
        rospy.loginfo('Waiting up to %.1f s for tf %s -> %s', wait,
                      self.odom_frame, ' or '.join(candidates))
        deadline = Deadline(wait, wall)
        while not rospy.is_shutdown():
            for frame in candidates:
                if self.buffer.can_transform(self.odom_frame, frame,
                                             rospy.Time(0)):
                    rospy.loginfo('Following tf %s -> %s', self.odom_frame, frame)
                    return frame
            if deadline.expired():
                break
            deadline.poll(20)
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

    def lookup(self):
        """(Pose2D, stamp) of the latest odom -> base transform, or None."""
        try:
            tf = self.buffer.lookup_transform(self.odom_frame, self.followed,
                                              rospy.Time(0))
        except tf2_ros.TransformException:
            return None
        t, q = tf.transform.translation, tf.transform.rotation
        return Pose2D(t.x, t.y, quat_to_angle(q)), tf.header.stamp

    def pick_simulator(self, simulators):
        """Under lockstep, on joining: follow the state of the simulator in
        ``simulators`` that broadcasts the followed transform, if any (a
        filter's transform has stamps that are not steps). None when
        blind (no transform followed)."""
        if self.followed is None:
            self.simulator = None
            return
        frames = yaml.safe_load(self.buffer.all_frames_as_yaml()) or {}
        broadcaster = frames.get(self.followed, {}).get('broadcaster')
        self.simulator = broadcaster if broadcaster in simulators else None

    def reading(self, now, granted):
        """(pose, stamp) for the tick at ``now``, or None.

        Under lockstep, following the transform of a simulator granted the
        same tick (in ``granted``), first wait for its state at that very
        time (it publishes it on the same grant). If it does not come
        within STATE_LIMIT wall seconds (the simulator died) the next
        ticks take what there is, until it catches up; the staleness check
        then ends the course.
        """
        if self.simulator is not None and self.simulator in granted:
            tick = to_ns(now)
            arrived = self.listener.wait(lambda: self._stamp() >= tick,
                                         self.state_wait)
            self.state_wait = lockstep.STATE_LIMIT if arrived else 0.0
        return self.lookup()

    def _stamp(self):
        """Stamp (ns) of the latest transform followed; 0 if none."""
        reading = self.lookup()
        return 0 if reading is None else to_ns(reading[1])
