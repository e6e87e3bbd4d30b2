"""What a course step hands the robot: a velocity :class:`Command`, and the limits on it.

No rospy here. The limits bound the parameters of every motion node.
"""
import math
from collections import namedtuple

from rbx1_nav.transform_utils import normalize_angle

__all__ = ['Command', 'STOP', 'DRIVE', 'TURN', 'PAUSE', 'DONE',
           'MAX_LINEAR_SPEED', 'MAX_ANGULAR_SPEED', 'MAX_DISTANCE', 'MAX_ANGLE',
           'MAX_TOLERANCE', 'pose_error', 'clamp']

Command = namedtuple('Command', 'linear angular')
Command.__doc__ = 'A velocity command: forward speed (m/s), turn rate (rad/s).'

STOP = Command(0.0, 0.0)

# The kinds of step (Step.kind), and a finished course's phase.
DRIVE, TURN, PAUSE, DONE = 'drive', 'turn', 'pause', 'done'

# No TurtleBot-class course needs more: past these, a value is a typo or a unit mix-up; no motion.
MAX_LINEAR_SPEED = 2.0           # m/s
MAX_ANGULAR_SPEED = 2 * math.pi  # rad/s
MAX_DISTANCE = 100.0             # m, one drive
MAX_ANGLE = 4 * math.pi          # rad, one turn (two full turns)
MAX_TOLERANCE = math.pi / 2      # rad


def pose_error(actual, expected):
    """(position error in m, heading error in rad) of one pose against another."""
    return (math.hypot(actual.x - expected.x, actual.y - expected.y),
            normalize_angle(actual.yaw - expected.yaw))


def clamp(value, low, high):
    """``value`` limited to [``low``, ``high``]."""
    return max(low, min(high, value))
