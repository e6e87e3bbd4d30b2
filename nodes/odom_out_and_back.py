#!/usr/bin/env python3
"""odom_out_and_back.py - drive 1 m out and back, measured by odometry via tf2.

A port of the ROS By Example node: the course itself (legs, pauses, the turn
tolerance, precise mode) lives in rbx1_nav.out_and_back; this node reads its
parameters, follows the odom -> base transform with tf2, feeds each pose to
the course and publishes the command it returns.

Publishes:  cmd_vel (geometry_msgs/Twist), relative, so a namespace works.
Parameters (private, book's values by default):
  ~linear_speed 0.15 m/s   ~goal_distance 1.0 m   ~angular_speed 0.5 rad/s
  ~goal_angle pi rad       ~angular_tolerance 1.0 deg   ~rate 20 Hz
  ~legs 2                  ~pause 1.0 s           ~precise false
  ~precise_gain 1.0 /s     ~precise_heading_gain 4.0 /s
  ~precise_min_linear_speed 0.005 m/s   ~precise_min_angular_speed 0.01 rad/s
  ~odom_frame odom         ~base_frame '' (try base_footprint, then base_link)
  ~tf_wait 5.0 s (for the first transform)   ~tf_timeout 1.0 s (staleness)
  ~start_delay 0.0 s (pause before moving, e.g. to let a bag recorder start)
Exit status: 0 after a completed course, 1 on bad parameters, missing or
stale tf, an error or an interruption. The robot is always sent a stop.
"""
import math
import sys
import threading
import time

import rospy
import tf2_ros
from geometry_msgs.msg import Twist
from rosgraph_msgs.msg import Clock

from rbx1_nav.out_and_back import (CourseConfig, OutAndBack, Pose2D,
                                   expected_end_pose, pose_error)
from rbx1_nav import params
from rbx1_nav.transform_utils import normalize_angle, quat_to_angle

BASE_FRAME_CANDIDATES = ('base_footprint', 'base_link')


class CourseAborted(Exception):
    """The course cannot go on; the message says why, for the log."""


# Course settings passed to CourseConfig as read (it checks them);
# ~angular_tolerance is read separately, in degrees as in the book.
COURSE_SETTINGS = ('linear_speed', 'goal_distance', 'angular_speed',
                   'goal_angle', 'legs', 'pause', 'precise', 'precise_gain',
                   'precise_heading_gain', 'precise_min_linear_speed',
                   'precise_min_angular_speed')


def read_settings():
    """Read and check every private parameter.

    Returns (CourseConfig, settings dict for the ROS side). Raises
    ValueError naming every unusable value.
    """
    problems = []

    def read(name, default, check, **options):
        try:
            return check('~' + name, rospy.get_param('~' + name, default),
                         **options)
        except ValueError as err:
            problems.append(str(err))
            return default

    defaults = CourseConfig()
    config = CourseConfig(**dict(
        (name, rospy.get_param('~' + name, getattr(defaults, name)))
        for name in COURSE_SETTINGS))
    config.angular_tolerance = math.radians(
        read('angular_tolerance', 1.0, params.number))
    problems.extend('~' + p for p in config.problems())
    positive = dict(minimum=0.0, allow_zero=False)
    settings = {
        'rate': read('rate', 20.0, params.number, minimum=1.0, maximum=1000.0),
        'tf_wait': read('tf_wait', 5.0, params.number, **positive),
        'tf_timeout': read('tf_timeout', 1.0, params.number, **positive),
        'start_delay': read('start_delay', 0.0, params.number, minimum=0.0),
        'odom_frame': read('odom_frame', 'odom', params.frame),
        'base_frame': read('base_frame', '', params.frame, allow_empty=True),
    }
    if problems:
        raise ValueError('; '.join(problems))
    return config.validate(), settings


def describe(config, settings):
    """One log line with every value the node will use."""
    base = settings['base_frame'] or 'auto (%s)' % ' or '.join(
        BASE_FRAME_CANDIDATES)
    text = ('linear_speed %.3f m/s, goal_distance %.3f m, angular_speed '
            '%.3f rad/s, goal_angle %.4f rad (%.1f deg), angular_tolerance '
            '%.2f deg, rate %.1f Hz, legs %d, pause %.1f s, precise %s, '
            'odom_frame %s, base_frame %s, tf_wait %.1f s, tf_timeout %.1f s, '
            'start_delay %.1f s'
            % (config.linear_speed, config.goal_distance, config.angular_speed,
               config.goal_angle, math.degrees(config.goal_angle),
               math.degrees(config.angular_tolerance), settings['rate'],
               config.legs, config.pause, 'on' if config.precise else 'off',
               settings['odom_frame'], base, settings['tf_wait'],
               settings['tf_timeout'], settings['start_delay']))
    if config.precise:
        text += (', precise_gain %.2f /s, precise_heading_gain %.2f /s, '
                 'precise_min_linear_speed %.4f m/s, '
                 'precise_min_angular_speed %.4f rad/s' % (
                     config.precise_gain, config.precise_heading_gain,
                     config.precise_min_linear_speed,
                     config.precise_min_angular_speed))
    return text


class OdomOutAndBack(object):
    """The ROS side of the course: tf2 in, cmd_vel out, stop on every exit."""

    def __init__(self, config, settings):
        self.config = config
        self.settings = settings
        self.odom_frame = settings['odom_frame']
        self.base_frame = settings['base_frame']
        self.cmd_vel = rospy.Publisher('cmd_vel', Twist, queue_size=5)
        # on_shutdown hooks run before rospy closes its topics (Ctrl-C,
        # rosnode kill, roslaunch ending), so this stop still goes out.
        rospy.on_shutdown(self.stop)
        self.tf_buffer = tf2_ros.Buffer()
        self.tf_listener = tf2_ros.TransformListener(self.tf_buffer)

    def stop(self):
        """Command zero velocity."""
        self.cmd_vel.publish(Twist())

    def publish(self, command):
        twist = Twist()
        twist.linear.x, twist.angular.z = command.linear, command.angular
        self.cmd_vel.publish(twist)

    def wait_for_clock(self):
        """Under /use_sim_time, wait (wall time) for the first /clock."""
        if not rospy.get_param('/use_sim_time', False):
            return
        if not rospy.Time.now().is_zero():
            return
        rospy.loginfo('/use_sim_time is set: waiting for /clock')
        try:
            rospy.wait_for_message('/clock', Clock,
                                   timeout=self.settings['tf_wait'])
        except rospy.ROSInterruptException:
            raise
        except rospy.ROSException:
            raise CourseAborted(
                '/use_sim_time is true but nothing publishes /clock after '
                '%.1f s (start the simulator with sim_speed set, or '
                'sim_clock.launch, or set /use_sim_time false)'
                % self.settings['tf_wait'])

    def watch_clock(self):
        """Under /use_sim_time, abort the course if /clock stops.

        rospy.Rate.sleep() waits for simulated time, so with a dead clock the
        control loop, and with it the stale-tf check, would block forever.
        This thread measures wall time (the one place the node does) and shuts
        the node down, robot stopped, when ROS time stands still for
        max(2 s, ~tf_timeout) of wall time.
        """
        if not rospy.get_param('/use_sim_time', False):
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
                    rospy.logerr('odom_out_and_back: /clock has not advanced '
                                 'for %.1f s of wall time (simulator or clock '
                                 'node gone?); stopped the robot', limit)
                    rospy.signal_shutdown('simulated clock stopped')
                    return

        threading.Thread(target=watch, name='clock_watchdog', daemon=True).start()

    def find_base_frame(self):
        """Wait up to ~tf_wait for odom -> base; pick the base frame."""
        candidates = ((self.base_frame,) if self.base_frame
                      else BASE_FRAME_CANDIDATES)
        deadline = rospy.Time.now() + rospy.Duration(self.settings['tf_wait'])
        poll = rospy.Rate(20)
        while not rospy.is_shutdown():
            for frame in candidates:
                if self.tf_buffer.can_transform(self.odom_frame, frame,
                                                rospy.Time(0)):
                    return frame
            if rospy.Time.now() >= deadline:
                break
            poll.sleep()
        if rospy.is_shutdown():
            raise rospy.ROSInterruptException('shutdown while waiting for tf')
        raise CourseAborted(
            'no transform from %s to %s after %.1f s: nothing is publishing '
            'the robot\'s odometry on tf. Start the robot first: roslaunch '
            'rbx1_nav fake_turtlebot.launch for the simulator, or the '
            'robot\'s driver (e.g. its bringup launch) on a real robot; or '
            'set ~odom_frame / ~base_frame to the frames your robot uses.'
            % (self.odom_frame, ' or '.join(candidates),
               self.settings['tf_wait']))

    def lookup(self):
        """(Pose2D, stamp) of the latest odom -> base transform, or None."""
        try:
            tf = self.tf_buffer.lookup_transform(self.odom_frame,
                                                 self.base_frame, rospy.Time(0))
        except tf2_ros.TransformException:
            return None
        t, q = tf.transform.translation, tf.transform.rotation
        return Pose2D(t.x, t.y, quat_to_angle(q)), tf.header.stamp

    def run(self):
        """Drive the course; return when done, raise CourseAborted if not."""
        self.wait_for_clock()
        self.watch_clock()
        rospy.loginfo('Waiting up to %.1f s for tf %s -> %s',
                      self.settings['tf_wait'], self.odom_frame,
                      self.base_frame or ' or '.join(BASE_FRAME_CANDIDATES))
        self.base_frame = self.find_base_frame()
        rospy.loginfo('Following tf %s -> %s', self.odom_frame, self.base_frame)
        if self.settings['start_delay'] > 0.0:
            rospy.loginfo('Starting in %.1f s', self.settings['start_delay'])
            rospy.sleep(self.settings['start_delay'])
        course = OutAndBack(self.config)
        timeout = rospy.Duration(self.settings['tf_timeout'])
        rate = rospy.Rate(self.settings['rate'])
        pose, last_stamp = None, None
        fresh_at = rospy.Time.now()
        while not rospy.is_shutdown():
            now = rospy.Time.now()
            reading = self.lookup()
            if reading is not None and (last_stamp is None
                                        or reading[1] > last_stamp):
                pose, last_stamp = reading
                fresh_at = now
            elif now - fresh_at > timeout:
                self.stop()
                raise CourseAborted(
                    'tf %s -> %s has not been updated for %.2f s (limit '
                    '~tf_timeout %.2f s): robot driver or simulator gone? '
                    'Stopped the robot.' % (
                        self.odom_frame, self.base_frame,
                        (now - fresh_at).to_sec(), timeout.to_sec()))
            if pose is None:  # found a moment ago; lookups may lag a cycle
                rate.sleep()
                continue
            self.publish(course.update(pose, now.to_sec()))
            for event in course.pop_events():
                rospy.loginfo(event)
            if course.done:
                break
            rate.sleep()
        if not course.done:
            raise rospy.ROSInterruptException('shutdown before the course ended')
        self.stop()
        self.summarize(course, pose)

    def summarize(self, course, final):
        """Log the final pose against the start and the course time."""
        start = course.start_pose
        error, heading = pose_error(final,
                                    expected_end_pose(start, self.config))
        rospy.loginfo(
            'Course complete in %.1f s: final pose relative to start in %s: '
            'dx %+.1f mm, dy %+.1f mm, dyaw %+.2f deg; error from the ideal '
            'end pose: position %.1f mm, heading %+.2f deg',
            course.elapsed, self.odom_frame, 1000.0 * (final.x - start.x),
            1000.0 * (final.y - start.y),
            math.degrees(normalize_angle(final.yaw - start.yaw)),
            1000.0 * error, math.degrees(heading))


def main():
    """Run the node; return the process exit status."""
    rospy.init_node('odom_out_and_back')
    try:
        config, settings = read_settings()
    except ValueError as err:
        rospy.logerr('odom_out_and_back: bad parameters, not moving: %s', err)
        return 1
    rospy.loginfo('odom_out_and_back: %s', describe(config, settings))
    node = OdomOutAndBack(config, settings)
    try:
        node.run()
        return 0
    except CourseAborted as err:
        rospy.logerr('odom_out_and_back: %s', err)
    except rospy.ROSInterruptException:
        rospy.logwarn('odom_out_and_back: interrupted; robot stopped')
    except Exception as err:  # log it, stop the robot, exit non-zero
        rospy.logerr('odom_out_and_back: %s: %s; stopping the robot',
                     type(err).__name__, err, exc_info=True)
    finally:
        node.stop()
    return 1


if __name__ == '__main__':
    status = main()
    rospy.signal_shutdown('odom_out_and_back finished')
    sys.exit(status)
