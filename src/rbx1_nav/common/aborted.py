"""The exception a motion node's runner raises when a course cannot go on: rospy-free, so the
pieces rbx1_nav.motion.runner_ros composes can raise it without importing the runner."""


class CourseAborted(Exception):
    """The course cannot go on; the message says why, for the log."""
