"""The ROS side of every motion node: a course in, the robot driven and stopped.

:func:`run_course_node` is a course node's main(); :class:`MotionRunner` owns the control loop
and the zero Twist on every exit path. Each fault: docs/safety.md; the pieces: docs/design.md.
"""
import threading

import rospy
from geometry_msgs.msg import Twist

from rbx1_nav.common.ros_time import time_moved_back_text
from rbx1_nav.common.node_ros import forget_command_line, start_node
from rbx1_nav.common.aborted import CourseAborted
from rbx1_nav.motion.runner.cmd_vel_ros import CmdVel
from rbx1_nav.motion.runner.other_drivers_ros import OtherDrivers
from rbx1_nav.motion.runner.loop import DropoutHold, FinalStops, NewestTransform
from rbx1_nav.motion.course.settle import GAVE_UP, Settle, moved_text
from rbx1_nav.motion.course.summary import stalls_text, summary_line
from rbx1_nav.motion.runner.tf_follow_ros import TF_TOPIC, TfFollower
from rbx1_nav.motion.runner.tf_guard import TransformGuard, top_speeds
from rbx1_nav.motion.runner.watchdogs_ros import OdomVelocities, TfAgeWarnings, watch_master
from rbx1_nav.transform_utils import Pose2D

__all__ = ['MotionRunner', 'guarded', 'run_course_node']

#: ROS s a course listens before its first command when another node publishes on its cmd_vel:
#: a course commands every tick, a teleop node at 10 Hz; a course slower than 2 Hz may be missed.
LISTEN = 1.0


class MotionRunner(object):
    """The control loop and the stop on every exit; ``settings``: the values of
    runner_params.common_params(); ``choose_clock(rate, wait, timeout, stop, tf_topic,
    odom_topic)``: the course's clock and link to the robot (rbx1_nav.entry.course_clock_ros). With
    ``require_tf`` false (open-loop courses) a robot without the transform runs the course
    blind: no staleness check and no final pose."""

    def __init__(self, name, settings, choose_clock, require_tf=True):
        self.name = name
        self.settings = settings
        self.require_tf = require_tf
        self.clock, self.link = choose_clock(
            settings['rate'], settings['tf_wait'], settings['tf_timeout'], self.stop,
            rospy.resolve_name(TF_TOPIC), rospy.resolve_name(OdomVelocities.TOPIC))
        self.cmd_vel = CmdVel(self.link)
        self.others = OtherDrivers(self.cmd_vel.pub.resolved_name)
        self.lock = threading.Lock()
        self.halted = False
        self.yielded = False  # another node drives the robot: send nothing, not even a stop
        # Before rospy closes its topics (Ctrl-C, rosnode kill, launch end): the stop goes out.
        rospy.on_shutdown(self.halt)
        self.tf = TfFollower(name, settings['odom_frame'], settings['base_frame'], self.link)
        self.velocities = OdomVelocities(name, self.link)
        self.tf_age = TfAgeWarnings(name, settings['max_tf_age'])
        self._started = False
        # The last course's DropoutHold, ticks (s from its first) and last tick (ROS time). Under
        # simulated time read a simulator at last_tick, not Time.now(): /clock may lag when busy.
        self.hold = None
        self.tick_times = []
        self.last_tick = None
        namespace = rospy.get_namespace().strip('/')  # log lines name a fleet's robot by it
        self.robot = namespace + ': ' if namespace else ''

    @property
    def odom_frame(self):
        return self.tf.odom_frame

    @property
    def followed(self):
        """The base frame found on tf; None before, or when blind."""
        return self.tf.followed

    def stop(self):
        """Command zero velocity; a no-op once rospy closed its topics (halt() stopped first),
        or when the course left the robot to another node."""
        if self.yielded:
            return
        try:
            self.cmd_vel.send(Twist())
        except rospy.ROSException:
            if not rospy.core.is_shutdown_requested():
                raise

    def halt(self):
        """Stop for good: the node is shutting down (any thread)."""
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
            self.clock.start(self.name)
            watch_master(self.name)
            self.others.watch(self.name)
            self._started = True

    def run(self, course, stay=False):
        """Drive ``course``: its final pose (None when blind), or CourseAborted or
        ROSInterruptException raised, robot stopped. ``stay``: another follows; no leave()."""
        self.start()
        self.yielded = False
        try:
            if self.tf.followed is None:
                self.tf.followed = self.tf.find_base_frame(
                    self.settings['tf_wait'], self.require_tf)
            self.cmd_vel.wait_for_listener(self.settings['tf_wait'])
            self._claim()
            self.others.arm()  # till the end, another node commanding motion is a fight
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
            self.others.disarm()
            self.tf.guard = None
        if not stay:
            self.leave()
        return final

    def _claim(self):
        """Leave the robot to a node already driving it. When another node publishes on cmd_vel,
        listen LISTEN s before the first command; if it drove meanwhile (a course's commands,
        stops too, or anyone's motion), CourseAborted, and nothing is sent, not even a stop."""
        if not self.others.hear(self.settings['tf_wait']):
            return
        self.pause(LISTEN)
        refused = self.others.refusal()
        if refused:
            self.yielded = True
            raise CourseAborted(refused)

    def pause(self, seconds):
        """Wait ``seconds`` of ROS time between courses."""
        self.clock.pause(seconds)

    def leave(self):
        """Tell the clock the last course has ended."""
        self.clock.leave()

    def _check_robot_is_ours(self):
        """CourseAborted, robot stopped, if another node drives it or its tf is not one robot's."""
        problem = self.others.other_driver() or (self.tf.guard and self.tf.guard.problem)
        if problem:
            self.stop()
            raise CourseAborted(problem)

    def _drive(self, course):
        """The control loop: the course's steps, then (with odometry) a wait for a still robot."""
        blind = self.tf.followed is None
        self.hold = DropoutHold(self.name, 'tf %s -> %s' % (self.tf.odom_frame, self.tf.followed),
                         self.settings['tf_timeout'], self.settings['link_grace'],
                         self.stop, rospy.logwarn, rospy.loginfo)
        robot = NewestTransform(Pose2D(0.0, 0.0, 0.0) if blind else None)
        settling = None
        self.tick_times = []
        start = None
        for now in self.clock.ticks():
            if start is None:
                start = now
            # From the integer ns: the same ticks give the same seconds whenever the course began.
            t = (now - start).to_sec()
            self.tick_times.append(t)
            self.last_tick = now
            self._check_robot_is_ours()
            robot.tick(now, None if blind else self.link.reading(self.tf, now))
            if settling is not None:
                self.stop()
                unacknowledged = self.cmd_vel.unacknowledged()
                if settling.done(self.hold.held(now, robot), robot, start, unacknowledged):
                    break
            elif not blind and self.hold.held(now, robot):
                self.publish(course.hold(t))
            elif robot.pose is not None:  # None: frame just found, lookups lag
                self._steer(course, robot, now, start, blind)
                if course.done:  # stop, and close the stall count
                    self.stop()
                    self.velocities.check(course, start)
                    course.stalls.end(t)
                    if blind:
                        break
                    settling = FinalStops(Settle(robot.pose, t, self.settings['settle_time'],
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
            self.tf_age.check(age, course.precise, self.tf.odom_frame, self.tf.followed)
        self.velocities.check(course, start)
        self.publish(course.update(robot.pose, self.tick_times[-1], age))
        for event in course.pop_events():
            rospy.loginfo(self.robot + event)

    def _settled(self, course, settle):
        """Log how the robot settled; a turn after the end counts in the course's yaw_total."""
        waited = self.tick_times[-1] - settle.ended
        if settle.state == GAVE_UP:
            rospy.logwarn('%s%s: the robot did not settle: %s %.1f s after the '
                          'course ended (~settle_timeout); the final pose below is the last read, '
                          'not a still one', self.robot, self.name,
                          'odometry still changing' if settle.sent else
                          'commands sent before the end not yet delivered', waited)
        elif settle.undelivered is not None:
            rospy.loginfo('%s%s: commands sent before the course ended were still on their way '
                          '%.2f s after it (a slow link); robot still %.2f s after the end',
                          self.robot, self.name, settle.undelivered - settle.ended, waited)
        moved = settle.moved()
        course.turned_after_end(moved.yaw)
        text = moved_text(moved)
        if text:
            rospy.logwarn('%s%s: %s; the final pose below is where it stands now%s', self.robot,
                          self.name, text, ' (precise mode checked its goal before that)'
                          if course.precise else '')

    def summarize(self, course, final):
        """Log the summary line (rbx1_nav.motion.course.summary)."""
        held = stalls_text(course.stalls, self.velocities.topic, self.velocities.heard())
        rospy.loginfo(summary_line(self.robot, course, final, self.tf.odom_frame,
                                   self.tick_times, held, self.hold.summary()))


def guarded(name, runner, work):
    """Run ``work()``, then stop the robot; exit status 0, or 1 (reason logged) if it raised."""
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
            # A signal shut rospy down from another thread (common.node_ros): no fault of ours.
            rospy.logwarn('%s: interrupted; robot stopped', name)
        else:
            rospy.logerr('%s: %s: %s; stopping the robot', name,
                         type(err).__name__, err, exc_info=True)
    finally:
        runner.stop()
    return 1


def run_course_node(name, specs, build_course, choose_clock, require_tf=True, doc=None):
    """A course node's main(), returning its exit status. ``specs``: all its parameters
    (common_params() among them); ``build_course(values)``: the Course; ``choose_clock``: as
    MotionRunner's; ``doc`` heads --help."""
    values = start_node(name, specs, doc)
    if values is None:
        return 1
    try:
        course = build_course(values)
    except ValueError as err:
        rospy.logerr('%s: bad parameters, not moving: %s', name, err)
        forget_command_line()
        return 1
    runner = MotionRunner(name, values, choose_clock, require_tf)

    def work():
        runner.summarize(course, runner.run(course))

    status = guarded(name, runner, work)
    if runner.yielded:  # it did not start: the master as it found it, as for a refused start
        forget_command_line()
    return status
