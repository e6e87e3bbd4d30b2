"""Motion: the courses (drive a distance, turn an angle, pause; closed loop on
odometry or open loop on time), the book's courses, teleop, and the one
runner that drives them on ROS and stops the robot on every exit path.

Knows no simulator and no filter: the same nodes run on a real robot.
Simulated time enters at one place, the course's clock, chosen once at
start-up (ticks_ros.course_ticks). ``*_ros.py`` modules import rospy; the others do not.
"""
