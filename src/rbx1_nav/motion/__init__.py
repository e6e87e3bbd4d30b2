"""Motion: the courses, the book's courses, teleop, and the runner that drives them on ROS
(docs/design.md). Knows no simulator or filter; simulated time enters only through the course's
clock (ticks_ros). ``*_ros.py`` modules import rospy; the others do not."""
