"""The pure course: what to drive and when a leg ends (the book's courses, their steps, precise
mode, the stall count, the summary). No rospy, and nothing of the runner."""
