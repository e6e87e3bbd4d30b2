"""The exception a motion node's runner raises when a course cannot go on.

Rospy-free, so every piece of the runner (rbx1_nav.motion.runner_ros and
the pieces it composes) can raise it without importing the runner.
"""


class CourseAborted(Exception):
    """The course cannot go on; the message says why, for the log."""
