"""Simulated time: the clock's pacing against the wall clock, and lockstep,
in which one owner (sim_clock) grants every step to the simulators and the
motion nodes and waits for each to answer. Everything of lockstep is here.

Nothing here engages on a real robot. ``*_ros.py`` modules import rospy.
"""
