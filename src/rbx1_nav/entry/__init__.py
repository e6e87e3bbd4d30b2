"""What a node's entry point chooses before it hands over, above the subsystems it joins: a
course's clock and link to the robot (course_clock_ros). Only nodes/ import it."""
