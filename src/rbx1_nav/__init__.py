"""rbx1_nav: odometry-driven motion for a differential-drive robot.

The modules in this package hold plain logic (no rospy) so they can be unit
tested without a ROS master; the scripts under ``nodes/`` wire them to ROS.
"""
