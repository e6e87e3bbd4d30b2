#!/usr/bin/env python3
"""fake_turtlebot: a kinematic TurtleBot base for simulation and tests.

A drop-in for the ArbotiX fake robot of ROS By Example. The motion model is
rbx1_nav.diff_drive; this node only reads parameters and wires it to ROS.

Subscribes:  cmd_vel (geometry_msgs/Twist)
Publishes:   odom (nav_msgs/Odometry), tf odom_frame -> base_frame,
             joint_states (sensor_msgs/JointState), ground_truth
             (nav_msgs/Odometry), imu_data (sensor_msgs/Imu, if ~publish_imu)
Parameters:  ~rate, ~odom_frame, ~base_frame, ~publish_tf, ~ground_truth_frame,
             ~imu_frame, ~publish_imu, ~left_wheel_joint, ~right_wheel_joint,
             ~pose_covariance_diagonal, ~twist_covariance_diagonal and every
             field of rbx1_nav.diff_drive.DiffDriveConfig (bounds in its
             CONFIG_LIMITS). ~rate is 50 Hz by default, 0.01 to 1000.
             A bad value is logged and the node exits with status 1.
"""
import math
import threading

import rospy
import tf2_ros
from geometry_msgs.msg import Quaternion, TransformStamped, Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, JointState

from rbx1_nav.diff_drive import (DEFAULT_COVARIANCE_DIAGONAL, DiffDriveConfig,
                                 DiffDriveSim, covariance_from_diagonal)
from rbx1_nav.params import flag, frame, number, number_list, text
from rbx1_nav.transform_utils import yaw_to_quaternion

WARN_PERIOD = 5.0  # s between repeats of the same warning
MAX_CATCH_UP = 1.0  # s of ROS time the loop replays step by step when late
# Bounds of ~rate (Hz): the loop steps every 1/~rate s of ROS time, so a
# huge rate would be a zero period (an endless catch-up) and a tiny one a
# sleep too long for the OS.
MIN_RATE, MAX_RATE = 0.01, 1000.0


def param(name, default, check, **options):
    """Parameter ``name`` checked by a rbx1_nav.params function."""
    return check(name, rospy.get_param(name, default), **options)


def model_config():
    """DiffDriveConfig filled from the node's private parameters."""
    raw = {name: rospy.get_param('~' + name, getattr(DiffDriveConfig, name))
           for name in DiffDriveConfig.names()}
    return DiffDriveConfig.from_params(raw, prefix='~')


def covariance_param(name):
    """A 6-variance covariance diagonal parameter, as a row-major 36-list."""
    diagonal = param(name, list(DEFAULT_COVARIANCE_DIAGONAL), number_list,
                     length=6, minimum=0.0, allow_zero=False)
    return diagonal, covariance_from_diagonal(diagonal)


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

    def __init__(self):
        self.rate = param('~rate', 50.0, number, minimum=MIN_RATE, maximum=MAX_RATE)
        self.odom_frame = param('~odom_frame', 'odom', frame)
        self.base_frame = param('~base_frame', 'base_footprint', frame)
        self.truth_frame = param('~ground_truth_frame', 'world', frame)
        self.imu_frame = param('~imu_frame', self.base_frame, frame)
        self.publish_tf = param('~publish_tf', True, flag)
        self.publish_imu = param('~publish_imu', False, flag)
        self.joints = [param('~left_wheel_joint', 'left_wheel_joint', text),
                       param('~right_wheel_joint', 'right_wheel_joint', text)]
        pose_diag, self.pose_cov = covariance_param('~pose_covariance_diagonal')
        twist_diag, self.twist_cov = covariance_param('~twist_covariance_diagonal')
        self.sim = DiffDriveSim(model_config())
        self.lock = threading.Lock()
        self.was_timed_out = True

        used = dict(vars(self.sim.config), rate=self.rate, odom_frame=self.odom_frame,
                    base_frame=self.base_frame, ground_truth_frame=self.truth_frame,
                    publish_tf=self.publish_tf, publish_imu=self.publish_imu,
                    imu_frame=self.imu_frame, wheel_joints=self.joints,
                    pose_covariance_diagonal=pose_diag,
                    twist_covariance_diagonal=twist_diag)
        rospy.loginfo('fake_turtlebot parameters: %s',
                      ', '.join('%s=%r' % item for item in sorted(used.items())))
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
        self.tf_pub = tf2_ros.TransformBroadcaster() if self.publish_tf else None
        rospy.Subscriber('cmd_vel', Twist, self.on_cmd_vel, queue_size=1)

    def on_cmd_vel(self, msg):
        """Queue a command; warn (throttled) about rejected or clamped ones."""
        with self.lock:
            problem = self.sim.command(msg.linear.x, msg.angular.z,
                                       rospy.Time.now().to_sec())
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
            except rospy.ROSTimeMovedBackwardsException:
                rospy.logwarn('fake_turtlebot: ROS time moved backwards; restarting')
                next_tick = None
            except rospy.ROSInterruptException:
                break

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
    rospy.init_node('fake_turtlebot')
    try:
        robot = FakeTurtleBot()
    except ValueError as err:
        rospy.logfatal('fake_turtlebot: %s', err)
        raise SystemExit(1)
    robot.spin()


if __name__ == '__main__':
    main()
