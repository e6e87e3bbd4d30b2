"""teleop_keyboard.py's keys to velocities (teleop), and its ROS side (teleop_ros)."""
