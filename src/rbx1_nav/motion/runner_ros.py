"""The ROS side of every motion node: a course in, the robot driven and stopped.

A motion node declares its private parameters (rbx1_nav.common.params.Param) and
how to build its course (a rbx1_nav.motion.course.Course) from their values;
:func:`run_course_node` does the rest: reads and checks the parameters
(with the common ones below), logs the values it uses, follows the
``odom_frame -> base_frame`` transform with tf2, feeds each pose to the
course, publishes its commands on ``cmd_vel``, and logs a summary line.

:class:`MotionRunner` owns the control loop and the stop; each other
concern is a piece it composes, beside it in rbx1_nav.motion: the
cmd_vel side (cmd_vel_ros), the tf follower (tf_follow_ros), the clock
(ticks_ros), the watchdogs (watchdogs_ros) and the summary line
(summary).

Safety, for every node that uses it: a zero Twist goes out on every exit
path (success, Ctrl-C, ``rosnode kill``, any exception). When the
transform stops updating for ``~tf_timeout``, or what arrives is stamped
that long ago, the robot is commanded zero and the course waits up to
``~link_grace`` more for it (a Wi-Fi dropout, rbx1_nav.motion.dropouts),
then carries on from the pose tf gives; past that, or when ``/clock``
stops under simulated time, it aborts, robot stopped.
It aborts too, robot stopped, when another node commands motion on its
cmd_vel while it drives (rbx1_nav.common.cmd_vel_watch.OtherDriver), or when
its transform comes from two nodes or jumps further than the robot can
move (rbx1_nav.motion.tf_guard). Exit status 0 only after a completed
course.

The clock (rbx1_nav.motion.ticks_ros) says when each tick comes and what
the robot's state is at it: on a real robot, a rate of ROS time; under
simulated time that steps with its nodes, the simulator's variant. The
start-up waits for the clock, the transform and a cmd_vel subscriber
(~tf_wait) count wall seconds, at any simulation speed: they wait for
other processes rather than for the robot, so a launch file need not
scale them with its sim_speed (and leave scaled values behind on the
master for a later rosrun).
"""
import threading

import rospy
from geometry_msgs.msg import Twist

from rbx1_nav.common import params
from rbx1_nav.common.params import param
from rbx1_nav.common.ros_time import time_moved_back_text
from rbx1_nav.common.node_ros import start_node
from rbx1_nav.common.aborted import CourseAborted
from rbx1_nav.motion.cmd_vel_ros import CmdVel
from rbx1_nav.motion.precise import Breakaway
from rbx1_nav.motion.loop import Hold, Reading, Settling
from rbx1_nav.motion.settle import GAVE_UP, SETTLE_PARAMS, Settle, moved_text
from rbx1_nav.motion.summary import stalls_text, summary_line
from rbx1_nav.motion.tf_follow_ros import TF_TOPIC, TfFollower
from rbx1_nav.motion.tf_guard import TransformGuard, top_speeds
from rbx1_nav.motion.ticks_ros import course_ticks
from rbx1_nav.motion.watchdogs_ros import (ClockWatchdog, StallWarnings,
                                           TfAgeWarnings, require_clock,
                                           watch_master)
from rbx1_nav.transform_utils import Pose2D

__all__ = ['MotionRunner', 'common_params', 'guarded',
           'run_course_node']


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
    ) + SETTLE_PARAMS


class MotionRunner(object):
    """The control loop and the stop on every exit; tf2 in, cmd_vel out.

    It composes one piece per concern: the cmd_vel side
    (rbx1_nav.motion.cmd_vel_ros), the tf follower
    (rbx1_nav.motion.tf_follow_ros), the clock
    (rbx1_nav.motion.ticks_ros), the watchdogs
    (rbx1_nav.motion.watchdogs_ros) and the summary line
    (rbx1_nav.motion.summary).

    ``settings`` holds the values of :func:`common_params`. With
    ``require_tf`` false (open-loop courses) a robot without the transform
    still runs the course, blind: no staleness check and no final pose.
    """

    def __init__(self, name, settings, require_tf=True):
        self.name = name
        self.settings = settings
        self.require_tf = require_tf
        self.ticks = course_ticks(settings['rate'], settings['tf_wait'],
                                  settings['tf_timeout'], self.stop,
                                  rospy.resolve_name(TF_TOPIC),
                                  rospy.resolve_name(StallWarnings.TOPIC))
        self.cmd_vel = CmdVel(self.ticks)
        self.lock = threading.Lock()
        self.halted = False
        # on_shutdown hooks run before rospy closes its topics (Ctrl-C,
        # rosnode kill, roslaunch ending), so this stop still goes out.
        rospy.on_shutdown(self.halt)
        self.tf = TfFollower(name, settings['odom_frame'], settings['base_frame'],
                             self.ticks)
        self.stalls = StallWarnings(name, self.ticks)
        self.tf_age = TfAgeWarnings(name, settings['max_tf_age'])
        self.clock_watchdog = ClockWatchdog(name, settings['tf_timeout'],
                                            self.stop)
        self._started = False
        self.hold = None  # the transform's dropouts, in the course driven last
        self.tick_times = []  # the control ticks (s) of the course driven last, from its first
        self._last_tick = None  # the ROS time of the last of them
        # Precise mode's creep speeds learned where the robot stuck: kept
        # for every course this runner drives.
        self.breakaway = Breakaway()
        # Progress and summary lines name the robot in a fleet: its namespace.
        namespace = rospy.get_namespace().strip('/')
        self.robot = namespace + ': ' if namespace else ''

    @property
    def odom_frame(self):
        """The odometry frame (~odom_frame)."""
        return self.tf.odom_frame

    @property
    def followed(self):
        """The base frame found on tf; None before, or when blind."""
        return self.tf.followed

    def stop(self):
        """Command zero velocity (a no-op once rospy has closed its topics:
        the shutdown hook :meth:`halt` has sent the stop by then)."""
        try:
            self.cmd_vel.send(Twist())
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
                self.cmd_vel.send(twist)

    def start(self):
        """Wait for the clock and start the watchdogs (once per node)."""
        if not self._started:
            require_clock(self.settings['tf_wait'])
            if self.ticks.watch_clock:
                self.clock_watchdog.start()
            watch_master(self.name)
            self.cmd_vel.watch_publishers(self.name)
            self._started = True

    def run(self, course, stay=False):
        """Drive ``course``; return the final pose (None when blind).

        Raises CourseAborted or rospy.ROSInterruptException if the course
        did not complete; the robot is stopped either way. With ``stay``,
        the clock is not told the course has ended (another follows at
        once: see :meth:`pause` and :meth:`leave`).
        """
        self.start()
        # From here to the end another node commanding motion on our
        # cmd_vel is a fight (rbx1_nav.common.cmd_vel_watch.OtherDriver).
        self.cmd_vel.others.arm()
        try:
            if self.tf.followed is None:
                self.tf.followed = self.tf.find_base_frame(
                    self.settings['tf_wait'], self.require_tf)
            self.cmd_vel.wait_for_listener(self.settings['tf_wait'])
            if self.tf.followed is not None:
                self.tf.guard = TransformGuard(
                    self.tf.odom_frame, self.tf.followed, *top_speeds(course))
            if self.settings['start_delay'] > 0.0:
                rospy.loginfo('Starting in %.1f s', self.settings['start_delay'])
                self.pause(self.settings['start_delay'])
            final = self._drive(course)
        except BaseException:
            self.leave()
            raise
        finally:
            self.cmd_vel.others.disarm()
            self.tf.guard = None
        if not stay:
            self.leave()
        return final

    def pause(self, seconds):
        """Wait ``seconds`` of ROS time between courses (see Ticks.pause)."""
        self.ticks.pause(seconds)

    def leave(self):
        """Tell the clock the last course has ended."""
        self.ticks.leave()

    def _check_robot_is_ours(self):
        """CourseAborted, robot stopped, when another node drives the robot
        or its transform is not one robot's (two publishers, a jump no
        robot at the course's speeds makes): the course cannot end where
        it should."""
        problem = self.cmd_vel.other_driver() or (
            self.tf.guard and self.tf.guard.problem)
        if problem:
            self.stop()
            raise CourseAborted(problem)

    def _drive(self, course):
        """The control loop of :meth:`run`: the course's steps, then (with
        odometry) the wait for a still robot; the pieces it asks are in
        rbx1_nav.motion.loop."""
        blind = self.tf.followed is None
        course.breakaway = self.breakaway
        self.hold = Hold(self.name, 'tf %s -> %s' % (self.tf.odom_frame, self.tf.followed),
                         self.settings['tf_timeout'], self.settings['link_grace'],
                         self.stop, rospy.logwarn, rospy.loginfo)
        robot = Reading(Pose2D(0.0, 0.0, 0.0) if blind else None)
        settling = None
        self.tick_times = []
        start = None
        for now in self.ticks.ticks():
            if start is None:
                start = now
            # Seconds from the ROS times' integer ns: the same ticks give
            # the same seconds whenever the course began.
            t = (now - start).to_sec()
            self.tick_times.append(t)
            self._last_tick = now
            self._check_robot_is_ours()
            robot.tick(now, None if blind else self.ticks.reading(self.tf, now))
            if settling is not None:
                self.stop()
                held = self.hold.held(now, robot)
                if settling.done(held, robot, start, self.cmd_vel.unacknowledged()):
                    break
            elif not blind and self.hold.held(now, robot):
                self.publish(course.hold(t))
            elif robot.pose is not None:  # None: found a moment ago, lookups may lag
                self._steer(course, robot, now, start, blind)
                if course.done:
                    self._end_steps(course, start)
                    if blind:
                        break
                    settling = Settling(Settle(robot.pose, t, self.settings['settle_time'],
                                               self.settings['settle_timeout']),
                                        self.cmd_vel.message_bytes())
        if not course.done or (settling is not None and settling.waiting):
            raise rospy.ROSInterruptException('shutdown before the course ended')
        self.stop()
        if settling is not None:
            self._settled(course, settling.settle)
        return None if blind else robot.pose

    def _steer(self, course, robot, now, start, blind):
        """One tick of the course's steps: the command for where the robot is."""
        age = 0.0 if blind else robot.age(now)
        if robot.fresh_at == now:  # a new transform this tick
            self.tf_age.check(age, course.predicts, self.tf.odom_frame, self.tf.followed)
        self.stalls.check(course, start)
        self.publish(course.update(robot.pose, self.tick_times[-1], age))
        for event in course.pop_events():
            rospy.loginfo(self.robot + event)

    def _end_steps(self, course, start):
        """The last step is done: stop, and close the stall count."""
        self.stop()
        self.stalls.check(course, start)
        course.stalls.end(self.tick_times[-1])

    def _settled(self, course, settle):
        """Say how the wait for a still robot after ``course`` ended, and
        count any turn after the end in the course's yaw total."""
        waited = self.tick_times[-1] - settle.ended
        if settle.state == GAVE_UP:
            rospy.logwarn('%s%s: the robot did not settle: odometry still '
                          '%s %.1f s after the course ended '
                          '(~settle_timeout); the final pose below is the '
                          'last read, not a still one', self.robot, self.name,
                          'odometry still changing' if settle.sent else
                          'commands sent before the end not yet delivered',
                          waited)
        elif settle.undelivered is not None:
            rospy.loginfo('%s%s: commands sent before the course ended were '
                          'still on their way %.2f s after it (a slow link); '
                          'robot still %.2f s after the end', self.robot,
                          self.name, settle.undelivered - settle.ended, waited)
        moved = settle.moved()
        course.yaw_total += moved.yaw
        text = moved_text(moved)
        if text:
            rospy.logwarn('%s%s: %s; the final pose below is where it stands '
                          'now%s', self.robot, self.name, text,
                          ' (precise mode checked its goal before that)'
                          if course.predicts else '')

    @property
    def last_tick(self):
        """ROS time of the last control tick of the course driven last.

        Under simulated time, ``rospy.Time.now()`` is the last /clock this
        process received, which may lag the course's own ticks on a loaded
        machine: read a simulator's state at this time instead."""
        return self._last_tick

    def summarize(self, course, final):
        """Log the final pose against the start, the course time, and the
        spells the robot stood still while commanded to move."""
        held = stalls_text(course.stalls, self.stalls.topic, self.stalls.heard())
        rospy.loginfo(summary_line(self.robot, course, final, self.tf.odom_frame,
                                   self.tick_times, held,
                                   self.hold.summary()))


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
