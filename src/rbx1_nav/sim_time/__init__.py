"""Simulated time: sim_clock's pacing and its lockstep, in which it grants every step to the
simulators, filters and courses and waits for each to answer (owner: lockstep, lockstep_ros;
member: member, member_ros; a course: course_member_ros). A real robot's course loads
switch_ros alone, to learn that none of it engages. ``*_ros.py`` modules import rospy.
"""
