#!/usr/bin/env python3
"""A stand-in driver that publishes NaN poses, as ROBOTIS' turtlebot3_fake_node does when its
``tb3_model`` parameter is missing (its wheel separation is then never set).

At ``~rate`` Hz (25; wall time: nothing here keeps simulated time) it publishes ``odom``
(nav_msgs/Odometry) and ``odom -> base_footprint`` on /tf with NaN in the position and the
quaternion and in the angular velocity, as that node does, and the same pose on ``odom_combined``
(geometry_msgs/PoseWithCovarianceStamped), the input odom_ekf.py takes from a robot_pose_ekf.
With ``~nan_after_motion`` true it publishes a valid pose (the origin, standing still) until
the first command to move arrives, then NaN: a driver that breaks mid-course.
It records every Twist it receives on ``cmd_vel`` and the node that sent it; the service
``~received`` (std_srvs/Trigger) answers them as JSON: ``{"connections": publishers connected
on cmd_vel now, "commands": [[node, linear.x, angular.z], ...]}``.
"""
import json
import threading

import rospy
from geometry_msgs.msg import PoseWithCovarianceStamped, TransformStamped, Twist
from nav_msgs.msg import Odometry
from std_srvs.srv import Trigger, TriggerResponse
from tf2_msgs.msg import TFMessage

NAN = float('nan')


def set_pose(pose, value):
    """Set ``value`` in ``pose``'s x, y and its quaternion's z, w (NaN: as the fake's; 0: the
    origin, its quaternion the identity)."""
    pose.position.x = pose.position.y = value
    q = pose.orientation
    q.x, q.y, q.z, q.w = 0.0, 0.0, value, 1.0 + value


def main():
    rospy.init_node('nan_driver')
    rate = rospy.get_param('~rate', 25.0)
    lock = threading.Lock()
    commands = []
    broken = threading.Event()
    if not rospy.get_param('~nan_after_motion', False):
        broken.set()

    def on_cmd(msg):
        with lock:
            commands.append([msg._connection_header['callerid'], msg.linear.x, msg.angular.z])
        if msg.linear.x or msg.angular.z:
            broken.set()

    cmd_sub = rospy.Subscriber('cmd_vel', Twist, on_cmd, queue_size=100)

    def on_received(_request):
        with lock:
            answer = {'connections': cmd_sub.get_num_connections(), 'commands': list(commands)}
        return TriggerResponse(success=True, message=json.dumps(answer))

    rospy.Service('~received', Trigger, on_received)
    odom_pub = rospy.Publisher('odom', Odometry, queue_size=10)
    # A publisher of its own, not tf2_ros's broadcaster: the same message on the wire.
    tf_pub = rospy.Publisher('/tf', TFMessage, queue_size=10)
    pose_pub = rospy.Publisher('odom_combined', PoseWithCovarianceStamped, queue_size=10)
    odom = Odometry()
    odom.header.frame_id, odom.child_frame_id = 'odom', 'base_footprint'
    tf = TransformStamped()
    tf.header.frame_id, tf.child_frame_id = 'odom', 'base_footprint'
    combined = PoseWithCovarianceStamped()
    combined.header.frame_id = 'odom_combined'
    combined.pose.covariance = [0.01 if i % 7 == 0 else 0.0 for i in range(36)]
    ticker = rospy.Rate(rate)
    while not rospy.is_shutdown():
        value = NAN if broken.is_set() else 0.0
        set_pose(odom.pose.pose, value)
        set_pose(combined.pose.pose, value)
        odom.twist.twist.angular.z = value
        p, t, r = odom.pose.pose, tf.transform.translation, tf.transform.rotation
        t.x, t.y, t.z = p.position.x, p.position.y, p.position.z
        r.x, r.y, r.z, r.w = p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w
        now = rospy.Time.now()
        odom.header.stamp = tf.header.stamp = combined.header.stamp = now
        try:
            odom_pub.publish(odom)
            tf_pub.publish(TFMessage([tf]))
            pose_pub.publish(combined)
            ticker.sleep()
        except rospy.ROSInterruptException:
            break


if __name__ == '__main__':
    main()
