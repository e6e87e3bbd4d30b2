"""The common ground every subsystem stands on: parameters, node start-up,
ROS time's texts, the arc a differential drive travels, the master and
cmd_vel watches, throttled warnings, ending a launch, publishing helpers,
and a node's part in lockstep simulated time (every timed node takes part).

Imports nothing from a subsystem (motion, sim, sim_time, calibration,
estimation). Each ``*_ros.py`` module imports rospy; the others do not.
"""
