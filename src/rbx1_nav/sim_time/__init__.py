"""Simulated time: the clock's pacing against the wall clock, sim_clock's
node, and the owner's side of lockstep, in which sim_clock grants every
step to the simulators and the motion nodes and waits for each to answer
(a member's side is rbx1_nav.common.lockstep_member: every timed node
takes part).

Nothing here engages on a real robot. ``*_ros.py`` modules import rospy.
"""
