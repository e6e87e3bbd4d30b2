"""The common ground every subsystem stands on: parameters, node start-up,
the master and cmd_vel watches, throttled warnings, publishing helpers.

Imports nothing from a subsystem (motion, sim, sim_time, calibration,
estimation). Each ``*_ros.py`` module imports rospy; the others do not.
"""
