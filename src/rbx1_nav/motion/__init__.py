"""Motion: the pure course (course/), the runner that drives it on ROS (runner/), teleop
(teleop/) and the course plot (plot/) (docs/design.md). Knows no simulator, filter or simulated
time: a course's clock is handed to the runner. ``*_ros.py`` modules import rospy."""
