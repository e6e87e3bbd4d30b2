"""The simulated robots: the kinematic differential-drive model, the MuJoCo
physics model, their parameters, and the ROS side that publishes odom, tf,
joint_states, ground_truth, imu_data and gps for one robot or a fleet.

Knows nothing of motion nodes. ``*_ros.py`` modules import rospy.
"""
