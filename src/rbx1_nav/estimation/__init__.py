"""Pose estimation: pose_ekf (robot_pose_ekf's job) and odom_ekf.

* :mod:`~rbx1_nav.estimation.ekf`: the filter maths, an extended Kalman
  filter over ``(x, y, yaw)`` driven by motion increments, with relative
  (gyro, visual odometry) and absolute (yaw, position) updates;
* :mod:`~rbx1_nav.estimation.sensors`: the sensor bookkeeping, each
  sensor's checked readings, its "not measured" components, whether it is
  active, and start-up;
* :mod:`~rbx1_nav.estimation.fusion`: :class:`GyroOdomFusion`, when the
  filter starts and restarts, and the sensor timeouts;
* :mod:`~rbx1_nav.estimation.filter_run`: what one run of the filter
  holds, from its start to a restart;
* :mod:`~rbx1_nav.estimation.relative_run` and
  :mod:`~rbx1_nav.estimation.gps_run`: how a run steps and which sensor
  does what in it, without and with robot_pose_ekf's GPS mode;
* :mod:`~rbx1_nav.estimation.status`: the texts for a person, the status,
  a silent sensor's warning, a second publisher of our transform;
* :mod:`~rbx1_nav.estimation.input_check`: the screen every reading
  passes before a filter uses it;
* :mod:`~rbx1_nav.estimation.pose_ekf`: pose_ekf's sensor messages as
  plain values, its estimate as messages;
* :mod:`~rbx1_nav.estimation.odom_ekf`: the fused pose as nav_msgs/Odometry.

No rospy outside the ``*_ros.py`` modules: times are float seconds, poses
are plain tuples. The nodes' ROS sides are
:mod:`~rbx1_nav.estimation.pose_ekf_ros` and
:mod:`~rbx1_nav.estimation.odom_ekf_ros`.
"""
