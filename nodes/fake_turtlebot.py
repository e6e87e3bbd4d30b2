#!/usr/bin/env python3
"""fake_turtlebot: a kinematic TurtleBot base for simulation and tests.

A drop-in for the ArbotiX fake robot of ROS By Example. The motion model is
rbx1_nav.diff_drive; this node only reads parameters and wires it to ROS.

Subscribes:  cmd_vel (geometry_msgs/Twist)
Publishes:   odom (nav_msgs/Odometry), tf odom_frame -> base_frame, static
             tf ground_truth_frame -> odom_frame (identity: odometry and
             the truth start together, so RViz shows both),
             joint_states (sensor_msgs/JointState), ground_truth
             (nav_msgs/Odometry), imu_data (sensor_msgs/Imu, if ~publish_imu),
             gps (nav_msgs/Odometry, if ~publish_gps: the true x, y in
             ~ground_truth_frame plus white noise of ~gps_noise m (1 sigma),
             at ~gps_rate Hz, with variance ~gps_noise^2; seeded by ~seed)
Parameters:  PARAMS below (--help lists them) and every field of
             rbx1_nav.diff_drive.DiffDriveConfig (bounds in its
             CONFIG_LIMITS). A bad value is logged and the node exits with
             status 1.
"""
import math
import threading

import numpy as np
import rospy
import tf2_ros
from geometry_msgs.msg import Quaternion, TransformStamped, Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, JointState

from rbx1_nav.diff_drive import (DEFAULT_COVARIANCE_DIAGONAL, DiffDriveConfig,
                                 DiffDriveSim, covariance_from_diagonal)
from rbx1_nav.params import (POSITIVE, flag, frame, number, number_list, param,
                             raw, text)
from rbx1_nav.ros import lockstep
from rbx1_nav.ros.node import start_node, until_shutdown
from rbx1_nav.transform_utils import yaw_to_quaternion

WARN_PERIOD = 5.0  # s between repeats of the same warning
MAX_CATCH_UP = 1.0  # s of ROS time the loop replays step by step when late
# Bounds of ~rate (Hz): the loop steps every 1/~rate s of ROS time, so a
# huge rate would be a zero period (an endless catch-up) and a tiny one a
# sleep too long for the OS.
MIN_RATE, MAX_RATE = 0.01, 1000.0
MAX_GPS_NOISE = 1000.0  # m, bound of ~gps_noise
GPS_UNKNOWN_VARIANCE = 1e6  # reported for z and the orientation (not measured)


COVARIANCE = dict(length=6, **POSITIVE)
PARAMS = (
    param('rate', 50.0, number, 'Hz', 'simulation steps per second',
          minimum=MIN_RATE, maximum=MAX_RATE),
    param('odom_frame', 'odom', frame, '', 'odometry frame'),
    param('base_frame', 'base_footprint', frame, '', 'robot frame'),
    param('ground_truth_frame', 'world', frame, '',
          'frame of ground_truth and gps; tf to odom_frame is static'),
    param('imu_frame', '', frame, '', "frame of imu_data; '' = base_frame",
          allow_empty=True),
    param('publish_tf', True, flag, '', 'publish odom_frame -> base_frame'),
    param('publish_imu', False, flag, '', 'publish the gyro on imu_data'),
    param('publish_gps', False, flag, '', 'publish noisy true x, y on gps'),
    param('gps_noise', 0.3, number, 'm', 'GPS noise (1 sigma)',
          maximum=MAX_GPS_NOISE, **POSITIVE),
    param('gps_rate', 1.0, number, 'Hz', 'GPS fixes per second',
          minimum=MIN_RATE, maximum=MAX_RATE),
    param('left_wheel_joint', 'left_wheel_joint', text, '', 'joint name'),
    param('right_wheel_joint', 'right_wheel_joint', text, '', 'joint name'),
    param('pose_covariance_diagonal', list(DEFAULT_COVARIANCE_DIAGONAL),
          number_list, '', 'odom pose variances x y z roll pitch yaw',
          **COVARIANCE),
    param('twist_covariance_diagonal', list(DEFAULT_COVARIANCE_DIAGONAL),
          number_list, '', 'odom twist variances', **COVARIANCE),
) + tuple(param(name, getattr(DiffDriveConfig, name), raw, '',
                'model setting, checked by rbx1_nav.diff_drive')
          for name in DiffDriveConfig.names())


def fill_odometry(msg, stamp, frame_id, child, pose, velocity):
    """Set header, planar pose and body twist of a nav_msgs/Odometry."""
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    msg.child_frame_id = child
    msg.pose.pose.position.x = pose.x
    msg.pose.pose.position.y = pose.y
    msg.pose.pose.orientation = Quaternion(*yaw_to_quaternion(pose.yaw))
    msg.twist.twist.linear.x, msg.twist.twist.angular.z = velocity
    return msg


class FakeTurtleBot:
    """Parameters, publishers and the fixed-rate loop around DiffDriveSim."""

    def __init__(self, values):
        self.rate = values['rate']
        self.odom_frame = values['odom_frame']
        self.base_frame = values['base_frame']
        self.truth_frame = values['ground_truth_frame']
        self.imu_frame = values['imu_frame'] or self.base_frame
        self.publish_tf = values['publish_tf']
        self.publish_imu = values['publish_imu']
        self.publish_gps = values['publish_gps']
        self.gps_noise = values['gps_noise']
        self.gps_rate = values['gps_rate']
        self.joints = [values['left_wheel_joint'], values['right_wheel_joint']]
        self.pose_cov = covariance_from_diagonal(values['pose_covariance_diagonal'])
        self.twist_cov = covariance_from_diagonal(values['twist_covariance_diagonal'])
        self.sim = DiffDriveSim(DiffDriveConfig.from_params(
            {name: values[name] for name in DiffDriveConfig.names()}, prefix='~'))
        self.lock = threading.Lock()
        self.was_timed_out = True
        if self.sim.config.cmd_timeout < 1.0 / self.rate:
            rospy.logwarn('fake_turtlebot: ~cmd_timeout (%g s) is shorter than one '
                          'step (1/~rate = %g s); the watchdog will stop the base '
                          'between most commands', self.sim.config.cmd_timeout,
                          1.0 / self.rate)

        # Room for a whole catch-up burst (MAX_CATCH_UP of steps published
        # at once), so a late wake-up does not drop odometry messages.
        queue = int(math.ceil(self.rate * MAX_CATCH_UP)) + 10
        self.odom_pub = rospy.Publisher('odom', Odometry, queue_size=queue)
        self.truth_pub = rospy.Publisher('ground_truth', Odometry, queue_size=queue)
        self.joint_pub = rospy.Publisher('joint_states', JointState, queue_size=queue)
        self.imu_pub = (rospy.Publisher('imu_data', Imu, queue_size=queue)
                        if self.publish_imu else None)
        self.gps_pub = (rospy.Publisher('gps', Odometry, queue_size=10)
                        if self.publish_gps else None)
        # Its own generator, so turning the GPS on leaves the odometry and
        # gyro noise of a given ~seed unchanged.
        seed = self.sim.config.seed
        self.gps_rng = np.random.default_rng(None if seed is None
                                             else [seed, 1])
        self.next_gps = None
        self.tf_pub = tf2_ros.TransformBroadcaster() if self.publish_tf else None
        self.static_tf = tf2_ros.StaticTransformBroadcaster()
        world = TransformStamped()
        world.header.stamp = rospy.Time.now()
        world.header.frame_id = self.truth_frame
        world.child_frame_id = self.odom_frame
        world.transform.rotation.w = 1.0
        self.static_tf.sendTransform(world)
        # Under lockstep, motion nodes report to this simulator, which
        # reports to sim_clock (rbx1_nav.lockstep).
        self.keeper = self.reporter = None
        if lockstep.enabled():
            self.keeper = lockstep.Keeper(rospy.get_name(), lockstep.NODE_TOPIC)
            self.reporter = lockstep.Reporter(lockstep.CLOCK_TOPIC)
            rospy.on_shutdown(lambda: self.reporter.leave(
                lockstep.to_ns(rospy.Time.now())))
        # Every command counts under lockstep, so none may be dropped.
        rospy.Subscriber('cmd_vel', Twist, self.on_cmd_vel, queue_size=100,
                         tcp_nodelay=True)

    def on_cmd_vel(self, msg):
        """Queue a command; warn (throttled) about rejected or clamped ones."""
        with self.lock:
            problem = self.sim.command(msg.linear.x, msg.angular.z,
                                       rospy.Time.now().to_sec())
        if self.keeper is not None:
            self.keeper.command_from(msg)
        if problem == 'non-finite':
            rospy.logwarn_throttle(WARN_PERIOD, 'fake_turtlebot: non-finite cmd_vel '
                                   '(%r, %r) rejected; stopping' % (msg.linear.x, msg.angular.z))
        elif problem == 'clamped':
            cfg = self.sim.config
            rospy.logwarn_throttle(WARN_PERIOD, 'fake_turtlebot: cmd_vel (%g, %g) clamped '
                                   'to |v| <= %g m/s, |w| <= %g rad/s' % (
                                       msg.linear.x, msg.angular.z,
                                       cfg.max_linear_speed, cfg.max_angular_speed))

    def spin(self):
        """Step the model on a fixed grid of ROS times and publish each step.

        Steps fall every 1/~rate s of ROS time. When the node wakes late (a
        busy CPU at a high sim speed) it catches up step by step, so the
        published stream is the same at any speed; only after more than
        MAX_CATCH_UP s behind does it skip ahead in one (still exact) step.
        """
        if self.keeper is not None:
            return self.spin_lockstep()
        period = rospy.Duration.from_sec(1.0 / self.rate)
        next_tick = None
        while not rospy.is_shutdown():
            now = rospy.Time.now()
            if now.is_zero():  # sim time has not started yet
                next_tick = None
            elif next_tick is None or now < next_tick - period:  # start or reset
                next_tick = now
            else:
                if (now - next_tick).to_sec() > MAX_CATCH_UP:
                    rospy.logwarn_throttle(WARN_PERIOD, 'fake_turtlebot: %.2f s behind '
                                           'ROS time; skipping ahead' % (now - next_tick).to_sec())
                    next_tick = now
                while next_tick <= now:
                    self.step(next_tick)
                    next_tick += period
            try:
                rospy.sleep(period if next_tick is None else next_tick - rospy.Time.now())
            except rospy.ROSTimeMovedBackwardsException as err:
                rospy.logwarn('fake_turtlebot: ROS time moved backwards by %.1f s: a '
                              'bag looping or the simulator restarted? Restarting '
                              'from the new time', err.time)
                next_tick = None
            except rospy.ROSInterruptException:
                break

    def spin_lockstep(self):
        """Step when the clock reaches a grid time or a member's next tick.

        Each step is published before the members handle it, so a motion
        node steers by the pose of its very tick; then the simulator waits
        for them (their reports and commands) and tells sim_clock how far
        time may go: to its next grid step or the next member tick.
        """
        period = int(round(1e9 / self.rate))
        while not rospy.is_shutdown() and rospy.Time.now().is_zero():
            rospy.rostime.wallsleep(0.01)
        now = lockstep.to_ns(rospy.Time.now())
        grid = now
        while not rospy.is_shutdown():
            if now >= grid:
                grid = now + period
            self.step(lockstep.from_ns(now))
            if not self.keeper.wait_allows(now + 1):
                return
            member = self.keeper.next_tick()
            target = grid if member is None else max(min(grid, member), now + 1)
            self.reporter.report(now, target)
            try:
                rospy.sleep(lockstep.from_ns(target) - rospy.Time.now())
            except rospy.ROSTimeMovedBackwardsException as err:
                rospy.logwarn('fake_turtlebot: ROS time moved backwards by %.1f s: a '
                              'bag looping or the simulator restarted? Restarting '
                              'from the new time', err.time)
                grid = 0
            except rospy.ROSInterruptException:
                return
            now = lockstep.to_ns(rospy.Time.now())

    def step(self, stamp):
        """Advance the model to ``stamp`` and publish the new state."""
        with self.lock:
            advanced = self.sim.step(stamp.to_sec())
        if advanced:
            self.report_watchdog()
            self.publish(stamp)

    def report_watchdog(self):
        """Log once each time the watchdog stops or releases the base."""
        timed_out = self.sim.timed_out
        if timed_out and not self.was_timed_out:
            rospy.loginfo('fake_turtlebot: no cmd_vel for %g s; stopping',
                          self.sim.config.cmd_timeout)
        self.was_timed_out = timed_out

    def publish(self, stamp):
        """Publish odom, its tf, joint states, ground truth and the gyro."""
        sim = self.sim
        odom = fill_odometry(Odometry(), stamp, self.odom_frame, self.base_frame,
                             sim.odom, sim.odom_velocity)
        odom.pose.covariance = self.pose_cov
        odom.twist.covariance = self.twist_cov
        self.odom_pub.publish(odom)

        if self.tf_pub:
            tf = TransformStamped()
            tf.header = odom.header
            tf.child_frame_id = self.base_frame
            tf.transform.translation.x = sim.odom.x
            tf.transform.translation.y = sim.odom.y
            tf.transform.rotation = odom.pose.pose.orientation
            self.tf_pub.sendTransform(tf)

        joints = JointState(name=self.joints, position=list(sim.wheel_angles),
                            velocity=list(sim.wheel_velocities))
        joints.header.stamp = stamp
        self.joint_pub.publish(joints)

        if self.truth_pub.get_num_connections():  # skip the work if unused
            self.truth_pub.publish(fill_odometry(Odometry(), stamp, self.truth_frame,
                                                 self.base_frame, sim.truth, sim.velocity))
        if self.imu_pub and self.imu_pub.get_num_connections():
            self.imu_pub.publish(self.imu_message(stamp))
        if self.gps_pub:
            self.publish_gps_fix(stamp)

    def publish_gps_fix(self, stamp):
        """Every 1/~gps_rate s: the true x, y plus white noise, on gps."""
        period = rospy.Duration.from_sec(1.0 / self.gps_rate)
        if self.next_gps is None or stamp + period < self.next_gps:
            self.next_gps = stamp  # start, or time moved backwards
        if stamp < self.next_gps:
            return
        self.next_gps += period
        if self.next_gps <= stamp:  # far behind: back on the grid from now
            self.next_gps = stamp + period
        noise = self.gps_rng.normal(0.0, self.gps_noise, 2)
        fix = Odometry()
        fix.header.stamp = stamp
        fix.header.frame_id = self.truth_frame
        fix.child_frame_id = self.base_frame
        fix.pose.pose.position.x = self.sim.truth.x + noise[0]
        fix.pose.pose.position.y = self.sim.truth.y + noise[1]
        fix.pose.pose.orientation.w = 1.0
        variance = self.gps_noise ** 2
        fix.pose.covariance = covariance_from_diagonal(
            [variance, variance] + [GPS_UNKNOWN_VARIANCE] * 4)
        fix.twist.covariance = covariance_from_diagonal(
            [GPS_UNKNOWN_VARIANCE] * 6)
        self.gps_pub.publish(fix)

    def imu_message(self, stamp):
        """sensor_msgs/Imu with the gyro's yaw and yaw rate (no accelerometer)."""
        yaw_var, rate_var = self.sim.gyro_variances(1.0 / self.rate)
        imu = Imu()
        imu.header.stamp = stamp
        imu.header.frame_id = self.imu_frame
        imu.orientation = Quaternion(*yaw_to_quaternion(self.sim.gyro_yaw))
        imu.orientation_covariance = [1e-6, 0, 0, 0, 1e-6, 0, 0, 0, yaw_var]
        imu.angular_velocity.z = self.sim.gyro_rate
        imu.angular_velocity_covariance = [1e-6, 0, 0, 0, 1e-6, 0, 0, 0, rate_var]
        imu.linear_acceleration_covariance[0] = -1.0  # "not measured"
        return imu


def main():
    values = start_node('fake_turtlebot', PARAMS, __doc__)
    if values is None:
        raise SystemExit(1)
    try:
        robot = FakeTurtleBot(values)
    except ValueError as err:
        rospy.logfatal('fake_turtlebot: %s', err)
        raise SystemExit(1)
    until_shutdown(robot.spin)


if __name__ == '__main__':
    main()
