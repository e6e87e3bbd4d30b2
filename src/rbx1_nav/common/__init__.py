"""The common ground every subsystem stands on: parameters, node start-up, ROS time's texts, the
arc a differential drive travels, the master, cmd_vel and tf publisher watches, throttled
warnings, ending a launch, publishing helpers. Imports nothing from a subsystem (motion, sim,
sim_time, calibration, estimation). Each ``*_ros.py`` module imports rospy; the others do not."""
