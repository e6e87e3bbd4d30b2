"""Simulated time: the clock's pacing against the wall clock, sim_clock's
node, and lockstep, in which sim_clock grants every step to the
simulators, the filters and the courses and waits for each to answer:
the owner's side (lockstep, lockstep_ros), a member's (member,
member_ros), and a course's clock as a member (stepping_ros,
course_member_ros).

Nothing here engages on a real robot: a course loads stepping_ros alone,
to learn that. ``*_ros.py`` modules import rospy.
"""
