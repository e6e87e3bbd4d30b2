"""The runner that drives a course on ROS: the control loop, cmd_vel, tf, the watchdogs, and the
clock and link to the robot it is handed (rbx1_nav.entry.course_clock_ros chooses them)."""
