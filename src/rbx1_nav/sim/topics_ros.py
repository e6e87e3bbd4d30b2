"""The ROS side of one simulated robot, shared by nodes/fake_turtlebot.py
(one robot) and nodes/fake_fleet.py (N robots in one process), so every
robot of a fleet has exactly the single robot's topics, frames and messages.

:class:`RobotTopics` wires one robot of the model (a
rbx1_nav.sim.diff_drive.FleetRobot) to ROS: cmd_vel in; odom, tf, joint_states,
ground_truth, imu_data and gps out. :func:`make_fleet` is the model the
parameters ask for, :func:`model_config` its settings. The loop that steps
the model is rbx1_nav.sim.loop_ros.
"""
import os

import numpy as np
import rospkg
import rospy
from geometry_msgs.msg import Quaternion, TransformStamped, Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, JointState
from tf2_msgs.msg import TFMessage

from rbx1_nav.sim.diff_drive import (DiffDriveConfig, DiffDriveFleet, DiffDriveSim,
                                      covariance_from_diagonal)
from rbx1_nav.sim.params import GPS_UNKNOWN_VARIANCE, WARN_PERIOD
from rbx1_nav.sim.physics import PhysicsConfig, PhysicsFleet
from rbx1_nav.common.publish_ros import synchronous_publisher
from rbx1_nav.common.rospy_private_ros import connection_header, connections, limit_send_wait
from rbx1_nav.common.tf_publishers import (OtherPublisherWatch, foreign_parent,
                                           robot_conflict_text)
from rbx1_nav.common.throttle import Throttle
from rbx1_nav.transform_utils import strip_leading_slash, yaw_to_quaternion

__all__ = ['RobotTopics', 'UnheldPublisher', 'fill_odometry', 'make_fleet', 'model_config']

CONFLICT_PERIOD = 30.0  # s between repeats of the second-publisher error
STALL = 1.0  # wall s a subscriber that stops reading may hold up a step


def model_config(values, log_name):
    """The model's configuration in the checked parameters ``values`` (a
    PhysicsConfig with ~physics, else a DiffDriveConfig); warns when
    ~cmd_timeout is shorter than a step. Raises ValueError for a bad value."""
    cls = PhysicsConfig if values['physics'] else DiffDriveConfig
    config = cls.from_params({name: values[name] for name in cls.names()},
                             prefix='~')
    if config.cmd_timeout < 1.0 / values['rate']:
        rospy.logwarn('%s: ~cmd_timeout (%g s) is shorter than one step '
                      '(1/~rate = %g s); the watchdog will stop the base '
                      'between most commands', log_name, config.cmd_timeout,
                      1.0 / values['rate'])
    return config


def make_fleet(values, size, log_name):
    """The model of ``size`` robots the checked ``values`` ask for: a
    PhysicsFleet (MuJoCo, with the installed URDF) with ~physics, else a
    DiffDriveFleet. Raises ValueError for a bad value and ImportError
    (saying how to install it) when ~physics finds no MuJoCo."""
    config = model_config(values, log_name)
    if not values['physics']:
        return DiffDriveSim(config) if size == 1 else DiffDriveFleet(size, config)
    urdf = os.path.join(rospkg.RosPack().get_path('rbx1_nav'), 'urdf', 'turtlebot.urdf')
    fleet = PhysicsFleet(size, config, urdf)
    rospy.loginfo('%s: physics robot (MuJoCo %s): %g kg on %s, motors %g N m, '
                  'deadband %g rad/s, %g encoder ticks per turn', log_name,
                  fleet.mujoco_version, config.mass, config.floor, config.motor_torque,
                  config.motor_deadband, config.encoder_ticks)
    return fleet


def fill_odometry(msg, stamp, frame_id, child, pose, velocity):
    """Set header, planar pose and body twist of a nav_msgs/Odometry (a new
    one, or one published before: rospy serializes a message as it is
    published, so the simulator fills the same ones each step)."""
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    msg.child_frame_id = child
    msg.pose.pose.position.x = pose.x
    msg.pose.pose.position.y = pose.y
    q = msg.pose.pose.orientation
    q.x, q.y, q.z, q.w = yaw_to_quaternion(pose.yaw)
    msg.twist.twist.linear.x, msg.twist.twist.angular.z = velocity
    return msg


def _topic(ns, name):
    """Topic ``name`` of the robot in namespace ``ns`` ('': the node's)."""
    return '%s/%s' % (ns, name) if ns else name


def _frame(ns, name):
    """Frame ``name`` of the robot in namespace ``ns`` (no leading slash;
    an empty name stays empty)."""
    return strip_leading_slash('%s/%s' % (ns, name)) if ns and name else name


class UnheldPublisher(rospy.Publisher):
    """A synchronous_publisher (rbx1_nav.common.publish_ros) that no
    subscriber holds up for long: a write waits at most STALL wall s for a
    subscriber that stopped reading (a terminal paused with Ctrl-Z, a host
    gone from the network); then rospy drops that connection, as a broken
    one, and publishing goes on (a roscpp subscriber connects again, a rospy
    one once restarted). rospy's queued publishers bound the wait with a
    thread per subscriber woken for every message: at a simulator's 50 Hz,
    a quarter of its CPU."""

    def publish(self, *args, **kwargs):
        for connection in connections(self):
            limit_send_wait(connection, STALL)
        super().publish(*args, **kwargs)


class OwnTfWatch:
    """Names another node publishing a robot's transform on its tf topic
    ``topic``, as pose_ekf does (a second robot started with the same
    frames), at once and then every CONFLICT_PERIOD s while it lasts. It
    subscribes only while another node publishes there (:meth:`follow`):
    hearing its own transforms cost the robot a quarter of its CPU."""

    def __init__(self, topic, child, log_name):
        self.topic, self.child, self.log_name = topic, child, log_name
        self.conflicts = OtherPublisherWatch(CONFLICT_PERIOD)
        self.sub = None

    def follow(self, graph):
        """Subscribe or not, by the master's ``graph``
        (rbx1_nav.common.master_ros.topic_graph)."""
        others = set(graph[0].get(self.topic, ())) - {rospy.get_name()}
        if others and self.sub is None:
            self.sub = rospy.Subscriber(self.topic, TFMessage, self.on_tf, queue_size=100)
        elif not others and self.sub is not None:
            self.sub.unregister()
            self.sub = None

    def on_tf(self, msg):
        caller = connection_header(msg).get('callerid', '?')
        parent = foreign_parent(caller, rospy.get_name(), msg.transforms, self.child)
        if parent and self.conflicts.seen(caller, rospy.Time.now().to_sec()):
            rospy.logerr('%s: %s', self.log_name, robot_conflict_text(
                caller, parent, self.child, self.topic))


class RobotTopics:
    """One simulated robot's topics, frames and log lines.

    ``robot`` is the model's view of the robot (read after each step),
    ``values`` the checked rbx1_nav.sim.params.PARAMS, ``lock`` the lock
    that guards the model between this cmd_vel callback and the step.

    With ``ns`` '' (fake_turtlebot.py) the topics are relative to the
    node's namespace, the frames are the parameters' values and tf goes to
    /tf and /tf_static, as tf2_ros's broadcasters send it (a launch file
    can remap them). With a robot name (fake_fleet.py) everything is in
    that namespace: topics ``ns/odom`` ..., frames ``ns/odom_frame``,
    ``ns/base_frame`` and ``ns/imu_frame`` (ground_truth_frame, the world
    all robots share, stays as it is), tf on ``ns/tf`` and
    ``ns/tf_static``. ``index`` (a robot's place in the fleet) gives each
    robot its own GPS noise for a given ~seed. Log lines start with
    ``log_name``.
    """

    def __init__(self, robot, values, lock, ns='', index=None,
                 log_name='fake_turtlebot'):
        self.robot = robot
        self.lock = lock
        self.log_name = log_name
        self.period = 1.0 / values['rate']
        self.odom_frame = _frame(ns, values['odom_frame'])
        self.base_frame = _frame(ns, values['base_frame'])
        self.truth_frame = values['ground_truth_frame']
        self.imu_frame = _frame(ns, values['imu_frame']) or self.base_frame
        self.gps_noise = values['gps_noise']
        self.gps_period = rospy.Duration.from_sec(1.0 / values['gps_rate'])
        self.joints = [values['left_wheel_joint'], values['right_wheel_joint']]
        self.pose_cov = covariance_from_diagonal(values['pose_covariance_diagonal'])
        self.twist_cov = covariance_from_diagonal(values['twist_covariance_diagonal'])
        self._make_messages()
        self.was_timed_out = True
        self.stopped_at = None  # when the watchdog last stopped the base
        self.throttle = Throttle(WARN_PERIOD)
        self._advertise(values, ns)
        # Its own generator, so turning the GPS on leaves the odometry and
        # gyro noise of a given ~seed unchanged.
        seed = robot.config.seed
        self.gps_rng = np.random.default_rng(
            None if seed is None else [seed, 1] + ([] if index is None else [index]))
        self.next_gps = None
        # A single robot (a fleet's robots each have a tf topic of their
        # own) names any other node publishing its transform.
        self.tf_watch = (OwnTfWatch(self.tf_pub.resolved_name, self.base_frame, log_name)
                         if values['publish_tf'] and not ns else None)
        self._publish_world(ns)
        # Under lockstep (rbx1_nav.sim.loop_ros.spin_simulator): the
        # simulator's membership, which counts and holds every command,
        # and the last step taken, the time each command is queued at
        # (None: ROS time).
        self.member = None
        self.step_time = None
        self.cmd_sub = rospy.Subscriber(_topic(ns, 'cmd_vel'), Twist, self.on_cmd_vel,
                                        queue_size=100, tcp_nodelay=True)

    def _make_messages(self):
        """The messages of each step, filled anew each time (fill_odometry)."""
        self.odom_msg = Odometry()
        self.odom_msg.pose.covariance = self.pose_cov
        self.odom_msg.twist.covariance = self.twist_cov
        self.truth_msg = Odometry()
        # odom's transform shares its header and orientation objects.
        tf = TransformStamped(header=self.odom_msg.header, child_frame_id=self.base_frame)
        tf.transform.rotation = self.odom_msg.pose.pose.orientation
        self.tf_msg = TFMessage([tf])

    def _advertise(self, values, ns):
        """The publishers of odom, ground_truth, joint_states, the gyro,
        GPS and tf (the last three as the parameters ask). Each writes its
        message before publish() returns: under lockstep a motion node then
        gets its tick's state before the step is reported, and at any speed
        it costs no thread woken per message; a subscriber that stops
        reading is dropped after STALL s (UnheldPublisher)."""
        def publisher(name, msg_class):
            return synchronous_publisher(name, msg_class, cls=UnheldPublisher)

        self.odom_pub = publisher(_topic(ns, 'odom'), Odometry)
        self.truth_pub = publisher(_topic(ns, 'ground_truth'), Odometry)
        self.joint_pub = publisher(_topic(ns, 'joint_states'), JointState)
        self.imu_pub = (publisher(_topic(ns, 'imu_data'), Imu)
                        if values['publish_imu'] else None)
        self.gps_pub = (publisher(_topic(ns, 'gps'), Odometry)
                        if values['publish_gps'] else None)
        # What tf2_ros's TransformBroadcaster and StaticTransformBroadcaster
        # do, on this robot's own topics when it has a namespace.
        self.tf_pub = (publisher(_topic(ns, 'tf') if ns else '/tf', TFMessage)
                       if values['publish_tf'] else None)

    def _publish_world(self, ns):
        """Latch the transform from the shared world to this robot's odom."""
        self.static_tf = rospy.Publisher(_topic(ns, 'tf_static') if ns else '/tf_static',
                                         TFMessage, queue_size=100, latch=True)
        world = TransformStamped()
        world.header.stamp = rospy.Time.now()
        world.header.frame_id = self.truth_frame
        world.child_frame_id = self.odom_frame
        world.transform.rotation.w = 1.0
        self.static_tf.publish(TFMessage([world]))

    def on_cmd_vel(self, msg):
        """Queue a command, or under lockstep hold it for the grant that
        counts it: a course granted the step being handled may send it
        before the simulator has stepped there."""
        if self.member is None or not self.member.arrived(
                self.cmd_sub.resolved_name, msg, (self, msg)):
            self.command(msg)

    def command(self, msg):
        """Queue a command from the last step (now without one); warn
        (throttled) about rejected or clamped ones."""
        now = self.step_time
        if now is None:
            now = rospy.Time.now().to_sec()
        with self.lock:
            problem = self.robot.command(msg.linear.x, msg.angular.z, now)
        if problem is None or not self.throttle.ready(problem, now):
            return
        if problem == 'non-finite':
            rospy.logwarn('%s: non-finite cmd_vel (%r, %r) rejected; stopping',
                          self.log_name, msg.linear.x, msg.angular.z)
        elif problem == 'clamped':
            cfg = self.robot.config
            rospy.logwarn('%s: cmd_vel (%g, %g) clamped to |v| <= %g m/s, '
                          '|w| <= %g rad/s', self.log_name, msg.linear.x,
                          msg.angular.z, cfg.max_linear_speed,
                          cfg.max_angular_speed)

    def report_watchdog(self, stamp):
        """Log once each time the watchdog stops or releases the base."""
        timed_out = self.robot.timed_out
        if timed_out and not self.was_timed_out:
            ran = self.robot.command_time  # the watchdog counts from it (None: clock reset)
            rospy.loginfo('%s: no cmd_vel for %g s%s; stopping', self.log_name,
                          self.robot.config.cmd_timeout,
                          '' if ran is None else ' (the last ran from %.3f s)' % ran)
            self.stopped_at = stamp
        elif self.was_timed_out and not timed_out and self.stopped_at is not None:
            rospy.loginfo('%s: cmd_vel again after %.2f s stopped by the watchdog',
                          self.log_name, (stamp - self.stopped_at).to_sec())
        self.was_timed_out = timed_out

    def publish(self, stamp, granted=True):
        """After a step: the watchdog's log lines, then odom, its tf, joint
        states, ground truth, the gyro and GPS. A message nobody subscribes
        to is not even made (rospy would drop it). A step on the way to a
        grant (``granted`` False: rbx1_nav.sim.loop_ros._step_at) sends
        only the sensor messages nodes use at every step: odom, the gyro
        and GPS."""
        self.report_watchdog(stamp)
        tf_pub = self.tf_pub if granted else None
        if self.odom_pub.get_num_connections() or (
                tf_pub and tf_pub.get_num_connections()):
            self.publish_odometry(stamp, tf_pub)
        robot = self.robot
        if granted and self.joint_pub.get_num_connections():  # robot_state_publisher, a bag
            joints = JointState(name=self.joints, position=robot.wheel_angles,
                                velocity=robot.wheel_velocities)
            joints.header.stamp = stamp
            self.joint_pub.publish(joints)

        if granted and self.truth_pub.get_num_connections():
            self.truth_pub.publish(fill_odometry(self.truth_msg, stamp, self.truth_frame,
                                                 self.base_frame, robot.truth,
                                                 robot.velocity))
        if self.imu_pub and self.imu_pub.get_num_connections():
            self.send_sensor(self.imu_pub, self.imu_message(stamp))
        if self.gps_pub:
            self.publish_gps_fix(stamp)

    def publish_odometry(self, stamp, tf_pub):
        """odom, and its tf on ``tf_pub`` (None: not)."""
        robot = self.robot
        odom_pose = robot.odom
        odom = fill_odometry(self.odom_msg, stamp, self.odom_frame, self.base_frame,
                             odom_pose, robot.odom_velocity)
        self.send_sensor(self.odom_pub, odom)

        if tf_pub:
            translation = self.tf_msg.transforms[0].transform.translation
            translation.x, translation.y = odom_pose.x, odom_pose.y
            self.send_sensor(tf_pub, self.tf_msg)  # counted: a course
            # starting under lockstep finds it at the same tick every run

    def publish_gps_fix(self, stamp):
        """Every 1/~gps_rate s: the true x, y plus white noise, on gps."""
        period = self.gps_period
        if self.next_gps is None or stamp + period < self.next_gps:
            self.next_gps = stamp  # start, or time moved backwards
        if stamp < self.next_gps:
            return
        self.next_gps += period
        if self.next_gps <= stamp:  # far behind: back on the grid from now
            self.next_gps = stamp + period
        noise = self.gps_rng.normal(0.0, self.gps_noise, 2)
        truth = self.robot.truth
        fix = Odometry()
        fix.header.stamp = stamp
        fix.header.frame_id = self.truth_frame
        fix.child_frame_id = self.base_frame
        fix.pose.pose.position.x = truth.x + noise[0]
        fix.pose.pose.position.y = truth.y + noise[1]
        fix.pose.pose.orientation.w = 1.0
        variance = self.gps_noise ** 2
        fix.pose.covariance = covariance_from_diagonal(
            [variance, variance] + [GPS_UNKNOWN_VARIANCE] * 4)
        fix.twist.covariance = covariance_from_diagonal(
            [GPS_UNKNOWN_VARIANCE] * 6)
        self.send_sensor(self.gps_pub, fix)

    def send_sensor(self, pub, msg):
        """Publish a sensor message a filter may read: under lockstep it is
        counted in the simulator's report, so the filter waits for it."""
        pub.publish(msg)
        if self.member is not None:
            self.member.sent(pub.resolved_name)

    def imu_message(self, stamp):
        """sensor_msgs/Imu with the gyro's yaw and yaw rate (no accelerometer)."""
        robot = self.robot
        yaw_var, rate_var = robot.gyro_variances(self.period)
        imu = Imu()
        imu.header.stamp = stamp
        imu.header.frame_id = self.imu_frame
        imu.orientation = Quaternion(*yaw_to_quaternion(robot.gyro_yaw))
        imu.orientation_covariance = [1e-6, 0, 0, 0, 1e-6, 0, 0, 0, yaw_var]
        imu.angular_velocity.z = robot.gyro_rate
        imu.angular_velocity_covariance = [1e-6, 0, 0, 0, 1e-6, 0, 0, 0, rate_var]
        imu.linear_acceleration_covariance[0] = -1.0  # "not measured"
        return imu
