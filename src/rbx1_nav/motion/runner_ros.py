"""The ROS side of every motion node: a course in, the robot driven and stopped.

A motion node declares its private parameters (rbx1_nav.common.params.Param) and
how to build its course (a rbx1_nav.motion.course.Course) from their values;
:func:`run_course_node` does the rest: reads and checks the parameters
(with the common ones below), logs the values it uses, follows the
``odom_frame -> base_frame`` transform with tf2, feeds each pose to the
course, publishes its commands on ``cmd_vel``, and logs a summary line.

Safety, for every node that uses it: a zero Twist goes out on every exit
path (success, Ctrl-C, ``rosnode kill``, any exception). When the
transform stops updating for ``~tf_timeout`` the robot is commanded zero
and the course waits up to ``~link_grace`` more for it (a Wi-Fi dropout,
rbx1_nav.motion.dropouts), then carries on from the pose tf gives; past that, or
when ``/clock`` stops under simulated time, it aborts, robot stopped.
Exit status 0 only after a completed course.

Under lockstep simulated time (rbx1_nav.sim_time.lockstep) the node is a member
while it drives: sim_clock grants it each control tick, at which the
simulator has published its state, and time waits for the tick's command;
the start-up waits for the clock, the transform and a cmd_vel subscriber
(~tf_wait) count wall seconds, since they wait for other processes rather
than for the robot.
"""
import collections
import math
import threading
import time

import rospy
import tf2_ros
import yaml
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry

from rbx1_nav.common import params
from rbx1_nav.motion.dropouts import HOLD, LOST, Dropouts
from rbx1_nav.common.ros_time import time_moved_back_text
from rbx1_nav.motion.command import pose_error
from rbx1_nav.motion.course import control_rates
from rbx1_nav.motion.precise import Breakaway
from rbx1_nav.common.params import param
from rbx1_nav.common import lockstep_member_ros as lockstep
from rbx1_nav.common.publish_ros import from_ns, synchronous_publisher, to_ns
from rbx1_nav.common.master_ros import (MasterWatch, gone_text, restarted_text,
                                 topic_graph)
from rbx1_nav.common.node_ros import start_node, wait_for_clock
from rbx1_nav.common.cmd_vel_watch_ros import watch_publishers
from rbx1_nav.common.ros_time import no_clock_text
from rbx1_nav.transform_utils import Pose2D, normalize_angle, quat_to_angle

BASE_FRAME_CANDIDATES = ('base_footprint', 'base_link')
WARN_PERIOD = 10.0  # s between warnings about an old transform or a stall


def common_params(rate):
    """The runner's own parameters; ``rate`` (Hz) is the node's default."""
    return (
        param('rate', float(rate), params.number, 'Hz', 'control rate',
              minimum=1.0, maximum=1000.0),
        param('odom_frame', 'odom', params.frame, '', 'odometry frame'),
        param('base_frame', '', params.frame, '',
              "robot frame; '' tries base_footprint, then base_link",
              allow_empty=True),
        param('tf_wait', 5.0, params.number, 's',
              'wait this long for /clock, the first transform and a cmd_vel '
              'subscriber', **params.POSITIVE),
        param('tf_timeout', 1.0, params.number, 's',
              'stop the robot when the transform is older than this',
              **params.POSITIVE),
        param('link_grace', 5.0, params.number, 's',
              'then wait this much longer for it (a Wi-Fi dropout) before '
              'giving up', minimum=0.0, maximum=600.0),
        param('max_tf_age', 0.1, params.number, 's',
              'warn when the transform steered by is older than this '
              '(a slow link to the robot)', **params.POSITIVE),
        param('start_delay', 0.0, params.number, 's',
              'pause before moving (e.g. for a bag recorder)', minimum=0.0),
    )


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


class _Deadline(object):
    """A wait's limit: in ROS time, or in wall time under lockstep."""

    def __init__(self, seconds, wall):
        self.wall = wall
        self.end = (time.monotonic() + seconds if wall
                    else rospy.Time.now() + rospy.Duration(seconds))

    def expired(self):
        return (time.monotonic() if self.wall else rospy.Time.now()) >= self.end

    def poll(self, hz):
        """Sleep one poll period (wall time under lockstep)."""
        if self.wall:
            rospy.rostime.wallsleep(1.0 / hz)
        else:
            rospy.sleep(1.0 / hz)


class CourseAborted(Exception):
    """The course cannot go on; the message says why, for the log."""


class MotionRunner(object):
    """tf2 in, cmd_vel out, the watchdogs, and a stop on every exit.

    ``settings`` holds the values of :func:`common_params`. With
    ``require_tf`` false (open-loop courses) a robot without the transform
    still runs the course, blind: no staleness check and no final pose.
    """

    def __init__(self, name, settings, require_tf=True):
        self.name = name
        self.settings = settings
        self.require_tf = require_tf
        self.odom_frame = settings['odom_frame']
        self.base_frame = settings['base_frame']  # '' = automatic
        self.followed = None  # the base frame found on tf
        # Under lockstep each command is on its way before the tick's report.
        self.lockstep = lockstep.Member() if lockstep.enabled() else None
        self.cmd_vel = (synchronous_publisher('cmd_vel', Twist)
                        if self.lockstep else
                        rospy.Publisher('cmd_vel', Twist, queue_size=5, tcp_nodelay=True))
        self.lock = threading.Lock()
        self.halted = False
        # on_shutdown hooks run before rospy closes its topics (Ctrl-C,
        # rosnode kill, roslaunch ending), so this stop still goes out.
        rospy.on_shutdown(self.halt)
        self.tf_buffer = tf2_ros.Buffer()
        self.tf_listener = _Listener(self.tf_buffer)
        # The velocities the robot measured, for Course.stalls (drained by
        # the control loop, so the course is only touched in one thread).
        self.velocities = collections.deque(maxlen=1000)
        self.odom_sub = rospy.Subscriber('odom', Odometry, self._on_odom,
                                         queue_size=100, tcp_nodelay=True)
        self._clock_ready = False
        # Lockstep: the simulator whose transform is followed (None: not
        # a simulator's), the members granted the current tick, and how
        # long (wall s) to wait for the simulator's state at a tick.
        self.simulator = None
        self.granted = set()
        self.state_wait = lockstep.STATE_LIMIT
        self.dropouts = None  # the transform's, in the course driven last
        # Precise mode's creep speeds learned where the robot stuck: kept
        # for every course this runner drives.
        self.breakaway = Breakaway()
        # Progress and summary lines name the robot in a fleet: its namespace.
        namespace = rospy.get_namespace().strip('/')
        self.robot = namespace + ': ' if namespace else ''

    def _on_odom(self, msg):
        twist = msg.twist.twist
        self.velocities.append((msg.header.stamp.to_sec(), twist.linear.x,
                                twist.angular.z))

    def _check_stalls(self, course):
        """Feed the robot's measured velocities to ``course.stalls``; warn
        (throttled) of each spell it stood still while commanded to move."""
        while self.velocities:
            spell = course.stalls.velocity(*self.velocities.popleft())
            if spell is not None:
                rospy.logwarn_throttle(
                    WARN_PERIOD, '%s: the robot stood still for %.2f s while '
                    'commanded to move: stopped by its watchdog (commands late '
                    'or lost on the way to it?) or held (motors off, bumper)'
                    % (self.name, spell))

    def _send(self, twist):
        """Publish on cmd_vel, counted for lockstep (the simulator steps on
        once it has them all)."""
        self.cmd_vel.publish(twist)
        if self.lockstep is not None:
            self.lockstep.sent(self.cmd_vel.resolved_name)

    def stop(self):
        """Command zero velocity (a no-op once rospy has closed its topics:
        the shutdown hook :meth:`halt` has sent the stop by then)."""
        try:
            self._send(Twist())
        except rospy.ROSException:
            if not rospy.core.is_shutdown_requested():
                raise

    def halt(self):
        """Stop for good: the node is shutting down (from any thread)."""
        with self.lock:
            self.halted = True
            self.stop()

    def publish(self, command):
        """Send a course command, unless the node is shutting down."""
        twist = Twist()
        twist.linear.x, twist.angular.z = command.linear, command.angular
        with self.lock:
            if not self.halted:
                self._send(twist)

    def wait_for_clock(self):
        """Under /use_sim_time, wait (wall time) for the first /clock."""
        if rospy.Time.now().is_zero():  # only under /use_sim_time
            rospy.loginfo('/use_sim_time is set: waiting for /clock')
        if not wait_for_clock(self.settings['tf_wait']):
            if rospy.is_shutdown():
                raise rospy.ROSInterruptException('shutdown waiting for /clock')
            raise CourseAborted(no_clock_text(self.settings['tf_wait']))

    def watch_clock(self):
        """Under /use_sim_time, shut the node down if /clock stops.

        rospy.Rate.sleep() waits for simulated time, so with a dead clock the
        control loop, and with it the stale-tf check, would block forever.
        This thread measures wall time (the one place the node does) and shuts
        the node down, robot stopped, when ROS time stands still for
        max(2 s, ~tf_timeout) of wall time. Under lockstep the node waits
        for grants instead, with a limit of its own (:meth:`_ticks`).
        """
        if not rospy.get_param('/use_sim_time', False) or self.lockstep is not None:
            return
        limit = max(2.0, self.settings['tf_timeout'])

        def watch():
            last, since = rospy.get_rostime(), time.monotonic()
            while not rospy.is_shutdown():
                rospy.rostime.wallsleep(0.1)
                now = rospy.get_rostime()
                if now != last:
                    last, since = now, time.monotonic()
                elif time.monotonic() - since > limit:
                    self.stop()
                    rospy.logerr('%s: /clock has not advanced for %.1f s of '
                                 'wall time (simulator or clock node gone?); '
                                 'stopped the robot', self.name, limit)
                    rospy.signal_shutdown('simulated clock stopped')
                    return

        threading.Thread(target=watch, name='clock_watchdog', daemon=True).start()

    def watch_master(self):
        """Say once when the master becomes unreachable, when it is back,
        and when it restarted (rbx1_nav.common.master_ros: polled from a thread of
        its own with a timeout, so no master call can block the control
        loop; gone only after a few failed polls in a row, so a lossy link
        does not make the warning come and go). ROS 1's topic connections
        are peer to peer and outlive the master, so the course goes on."""
        name = self.name
        MasterWatch(name, on_gone=lambda uri, problem: rospy.logwarn(
            gone_text(name, uri, problem)),
            on_back=lambda uri: rospy.loginfo('%s: the ROS master at %s is '
                                              'back', name, uri),
            on_restarted=lambda uri: rospy.logwarn(restarted_text(name, uri))
        ).start()

    def start(self):
        """Wait for the clock and start the watchdogs (once per node)."""
        if not self._clock_ready:
            self.wait_for_clock()
            self.watch_clock()
            self.watch_master()
            watch_publishers(self.name, [self.cmd_vel.resolved_name],
                             own=rospy.get_name())
            self._clock_ready = True

    def find_base_frame(self):
        """Wait up to ~tf_wait for odom -> base; return the base frame or None."""
        candidates = ((self.base_frame,) if self.base_frame
                      else BASE_FRAME_CANDIDATES)
        rospy.loginfo('Waiting up to %.1f s for tf %s -> %s',
                      self.settings['tf_wait'], self.odom_frame,
                      ' or '.join(candidates))
        deadline = self._deadline(self.settings['tf_wait'])
        while not rospy.is_shutdown():
            for frame in candidates:
                if self.tf_buffer.can_transform(self.odom_frame, frame,
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
                                             ' or '.join(candidates),
                                             self.settings['tf_wait']))
        if not self.require_tf:
            rospy.logwarn('%s: %s; running the course open loop without a '
                          'position report', self.name, problem)
            return None
        raise CourseAborted(
            '%s. Start the robot first: roslaunch rbx1_nav fake_turtlebot.launch '
            'for the simulator, or the robot\'s driver (e.g. its bringup '
            'launch) on a real robot; or set ~odom_frame / ~base_frame to the '
            'frames your robot uses.' % problem)

    def wait_for_listener(self):
        """Wait up to ~tf_wait for the driver to subscribe to cmd_vel.

        Commands published before the connection is made are lost, which
        would shorten the first move of an open-loop course.
        """
        deadline = self._deadline(self.settings['tf_wait'])
        while not self._listening():
            if rospy.is_shutdown():
                raise rospy.ROSInterruptException('shutdown while waiting')
            if deadline.expired():
                if self.cmd_vel.get_num_connections():
                    raise CourseAborted(
                        '/lockstep is set but the node taking %s (%s) is not '
                        'granted lockstep steps on %s after %.1f s: start the '
                        'simulator with lockstep too, or set /lockstep false'
                        % (self.cmd_vel.resolved_name, ', '.join(sorted(
                            c.endpoint_id for c in self.cmd_vel.impl.connections)),
                           lockstep.GRANT_TOPIC, self.settings['tf_wait']))
                raise CourseAborted('nothing subscribes to %s after %.1f s: %s'
                                    % (self.cmd_vel.resolved_name,
                                       self.settings['tf_wait'],
                                       self._listener_hint()))
            deadline.poll(50)

    def _listening(self):
        """True once the driver takes cmd_vel; under lockstep, once a
        simulator that takes part in it does (it counts every command, so
        none may go out before its connection is up)."""
        takers = {c.endpoint_id for c in self.cmd_vel.impl.connections}
        if self.lockstep is None:
            return bool(takers)
        return bool(takers & self.lockstep.simulators())

    def _deadline(self, seconds):
        return _Deadline(seconds, wall=self.lockstep is not None)

    def _listener_hint(self):
        """Where the velocity commands could go instead, from the master."""
        graph = topic_graph()
        if graph is None:  # the master is gone too: nothing to suggest
            return 'is the robot driver running?'
        _, subscribers, types = graph
        topics = sorted(topic for topic in subscribers
                        if types.get(topic) == 'geometry_msgs/Twist')
        if not topics:
            return ('no node takes geometry_msgs/Twist commands: is the robot '
                    'driver running?')
        return ('these topics take Twist commands: %s. Remap to the driver\'s, '
                'e.g. cmd_vel:=%s' % (', '.join(topics), topics[0]))

    def lookup(self):
        """(Pose2D, stamp) of the latest odom -> base transform, or None."""
        try:
            tf = self.tf_buffer.lookup_transform(self.odom_frame,
                                                 self.followed, rospy.Time(0))
        except tf2_ros.TransformException:
            return None
        t, q = tf.transform.translation, tf.transform.rotation
        return Pose2D(t.x, t.y, quat_to_angle(q)), tf.header.stamp

    def run(self, course):
        """Drive ``course``; return the final pose (None when blind).

        Raises CourseAborted or rospy.ROSInterruptException if the course
        did not complete; the robot is stopped either way.
        """
        self.start()
        if self.followed is None:
            self.followed = self.find_base_frame()
        self.wait_for_listener()
        if self.settings['start_delay'] > 0.0:
            rospy.loginfo('Starting in %.1f s', self.settings['start_delay'])
            rospy.sleep(self.settings['start_delay'])
        try:
            return self._drive(course)
        finally:
            if self.lockstep is not None:
                self.lockstep.leave()

    def _drive(self, course):
        """The control loop of :meth:`run`."""
        blind = self.followed is None
        course.breakaway = self.breakaway
        self.dropouts = Dropouts(self.settings['tf_timeout'],
                                 self.settings['link_grace'])
        pose = Pose2D(0.0, 0.0, 0.0) if blind else None
        last_stamp = fresh_at = None
        self.tick_times = []
        for now in self._ticks(blind):
            self.tick_times.append(now.to_sec())
            if fresh_at is None:
                fresh_at = now
            reading = None if blind else self._reading(now)
            if reading is not None and (last_stamp is None
                                        or reading[1] > last_stamp):
                pose, last_stamp = reading
                fresh_at = now
            if not blind and self._held(now, fresh_at):
                self.publish(course.hold(now.to_sec()))
                continue
            if pose is None:  # found a moment ago; lookups may lag a cycle
                continue
            age = 0.0 if blind else (now - last_stamp).to_sec()
            if fresh_at == now:  # a new transform this tick
                self._check_age(age, course.predicts)
            self._check_stalls(course)
            self.publish(course.update(pose, now.to_sec(), age))
            for event in course.pop_events():
                rospy.loginfo(self.robot + event)
            if course.done:
                break
        if not course.done:
            raise rospy.ROSInterruptException('shutdown before the course ended')
        self.stop()
        self._check_stalls(course)
        course.stalls.end(self.tick_times[-1])
        return None if blind else pose

    @property
    def last_tick(self):
        """ROS time of the last control tick of the course driven last.

        Under simulated time, ``rospy.Time.now()`` is the last /clock this
        process received, which may lag the course's own ticks (granted
        to it under lockstep) on a loaded machine: read a simulator's
        state at this time instead."""
        return rospy.Time.from_sec(self.tick_times[-1])

    def _held(self, now, fresh_at):
        """Ride out a stale transform (rbx1_nav.motion.dropouts): True while the
        robot is to be held (commanded zero); CourseAborted past
        ~link_grace."""
        tick = self.dropouts.tick(now.to_sec(), fresh_at.to_sec())
        where = 'tf %s -> %s' % (self.odom_frame, self.followed)
        if tick.state == LOST:
            self.stop()
            raise CourseAborted(
                '%s has not been updated for %.2f s (limit ~tf_timeout %.2f s '
                '+ ~link_grace %.2f s): robot driver or simulator gone, or the '
                'link to the robot down? Stopped the robot.' % (
                    where, tick.stale, self.dropouts.timeout, self.dropouts.grace))
        if tick.began:
            rospy.logwarn('%s: %s has not been updated for %.2f s (~tf_timeout): '
                          'a link dropout? Holding the robot (zero velocity) and '
                          'waiting up to ~link_grace %.1f s for it', self.name,
                          where, tick.stale, self.dropouts.grace)
        elif tick.ended is not None:
            rospy.loginfo('%s: %s is back after %.2f s; carrying on from where '
                          'it says the robot is', self.name, where, tick.ended)
        return tick.state == HOLD

    def _check_age(self, age, predicts):
        """Warn (at most every WARN_PERIOD s) when the transform steered
        by is ``age`` s old, more than ~max_tf_age: the robot has moved on
        since."""
        limit = self.settings['max_tf_age']
        if age > limit:
            rospy.logwarn_throttle(
                WARN_PERIOD, '%s: tf %s -> %s is %.3f s old when used (limit '
                '~max_tf_age %.3f s): a slow link to the robot or a busy machine; '
                '%s' % (self.name, self.odom_frame, self.followed, age, limit,
                        'precise mode adds the commands sent since' if predicts
                        else 'the course steers by where the robot was'))

    def _ticks(self, blind):
        """The control ticks (ROS times), at ~rate; under lockstep, as a
        member of the simulator's gate."""
        if self.lockstep is None:
            rate = rospy.Rate(self.settings['rate'])
            while not rospy.is_shutdown():
                yield rospy.Time.now()
                rate.sleep()
            return
        member = self.lockstep
        try:
            member.join(self.settings['tf_wait'])
        except lockstep.JoinError as err:
            raise CourseAborted('/lockstep is set but this node cannot join: %s. '
                                'Start the simulator with lockstep too, or set '
                                '/lockstep false' % err)
        self.simulator = None if blind else self._simulator()
        period = int(round(1e9 / self.settings['rate']))
        limit = max(lockstep.GRANT_LIMIT, self.settings['tf_timeout'])
        while True:
            granted = member.wait_grant(limit)
            if granted is None:
                if rospy.is_shutdown():
                    return
                self.stop()
                raise CourseAborted(
                    '/clock has not advanced: no lockstep step granted for %.1f s '
                    'of wall time (sim_clock gone?); stopped the robot' % limit)
            action, tick, grant = granted
            self.granted = set(grant.members)
            if action == lockstep.BACK:
                raise rospy.ROSTimeMovedBackwardsException(
                    (member.follower.handled - tick) * 1e-9)
            yield from_ns(tick)
            member.report(tick, tick + period)

    def _simulator(self):
        """The lockstep simulator that broadcasts the followed transform, or
        None (a filter's, whose stamps are not steps)."""
        frames = yaml.safe_load(self.tf_buffer.all_frames_as_yaml()) or {}
        broadcaster = frames.get(self.followed, {}).get('broadcaster')
        return broadcaster if broadcaster in self.lockstep.simulators() else None

    def _reading(self, now):
        """(pose, stamp) for the tick at ``now``, or None.

        Under lockstep, following the transform of a simulator granted the
        same tick, first wait for its state at that very time (it publishes
        it on the same grant). If it does not come within STATE_LIMIT wall
        seconds (the simulator died) the next ticks take what there is,
        until it catches up; the staleness check then ends the course.
        """
        if self.simulator is not None and self.simulator in self.granted:
            tick = to_ns(now)
            arrived = self.tf_listener.wait(lambda: self._stamp() >= tick,
                                            self.state_wait)
            self.state_wait = lockstep.STATE_LIMIT if arrived else 0.0
        return self.lookup()

    def _stamp(self):
        """Stamp (ns) of the latest transform followed; 0 if none."""
        reading = self.lookup()
        return 0 if reading is None else to_ns(reading[1])

    def summarize(self, course, final):
        """Log the final pose against the start, the course time, and the
        spells the robot stood still while commanded to move."""
        stalls = course.stalls
        if self.odom_sub.get_num_connections() == 0:
            held = 'unknown (nothing on %s)' % self.odom_sub.resolved_name
        else:
            held = ('%d times, %.1f s in all (its watchdog, or commands '
                    'late)' % (stalls.count, stalls.seconds)
                    if stalls.count else 'never')
        dropouts = self.dropouts.summary()
        if final is None:
            rospy.loginfo('%sCourse complete in %.1f s (no odometry: final pose '
                          'unknown); stood still while commanded: %s; link '
                          'dropouts ridden out: %s', self.robot, course.elapsed,
                          held, dropouts)
            return
        start = course.start_pose
        error, heading = pose_error(final, course.ideal_end(start))
        rospy.loginfo(
            '%sCourse complete in %.1f s: final pose relative to start in %s: '
            'dx %+.1f mm, dy %+.1f mm, dyaw %+.2f deg; error from the ideal '
            'end pose: position %.1f mm, heading %+.2f deg; control loop '
            '%.1f Hz mean, %d Hz slowest second; stood still while commanded: '
            '%s; link dropouts ridden out: %s',
            self.robot, course.elapsed, self.odom_frame, 1000.0 * (final.x - start.x),
            1000.0 * (final.y - start.y),
            math.degrees(normalize_angle(final.yaw - start.yaw)),
            1000.0 * error, math.degrees(heading),
            *control_rates(self.tick_times), held, dropouts)


def guarded(name, runner, work):
    """Run ``work()``; log why it failed; stop the robot; return the status.

    0 when ``work`` returned, 1 when it raised (CourseAborted, an
    interruption, any exception).
    """
    try:
        work()
        return 0
    except CourseAborted as err:
        rospy.logerr('%s: %s', name, err)
    except rospy.ROSTimeMovedBackwardsException as err:
        rospy.logerr('%s: %s', name, time_moved_back_text(err.time, 'Stopped the robot.'))
    except rospy.ROSInterruptException:
        rospy.logwarn('%s: interrupted; robot stopped', name)
    except Exception as err:  # log it, stop the robot, exit non-zero
        if rospy.core.is_shutdown_requested():
            # A signal shuts rospy down in another thread (rbx1_nav.common.node_ros):
            # a call it closed under us is the interruption, not a fault.
            rospy.logwarn('%s: interrupted; robot stopped', name)
        else:
            rospy.logerr('%s: %s: %s; stopping the robot', name,
                         type(err).__name__, err, exc_info=True)
    finally:
        runner.stop()
    return 1


def run_course_node(name, specs, build_course, require_tf=True, doc=None):
    """The whole main() of a course node; returns its exit status.

    ``specs`` are all the node's parameters, :func:`common_params` among
    them; ``build_course(values)`` returns the
    :class:`rbx1_nav.motion.course.Course` to drive; ``doc`` (the node's
    docstring) heads its ``--help``.
    """
    values = start_node(name, specs, doc)
    if values is None:
        return 1
    try:
        course = build_course(values)
    except ValueError as err:
        rospy.logerr('%s: bad parameters, not moving: %s', name, err)
        return 1
    runner = MotionRunner(name, values, require_tf)

    def work():
        runner.summarize(course, runner.run(course))

    return guarded(name, runner, work)
