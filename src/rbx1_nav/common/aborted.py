"""The exception a course cannot go on with, robot stopped: raised by the motion runner's
pieces and by simulated time's side of a course (sim_time), caught by the runner; rospy-free."""


class CourseAborted(Exception):
    """The course cannot go on; the message says why, for the log."""
