"""Poses a driver publishes that nothing can use: NaN or infinite, or a rotation that is not a
unit quaternion. tf2 drops such a transform before a listener sees it (logging TF_NAN_INPUT or
TF_DENORMALIZED_QUATERNION for each one), so to a course that only asks tf, a driver publishing
them looks absent. The course reads its transform on /tf itself (and ``odom``), and names the
node and the fault with these texts. No rospy.
"""
import math

__all__ = ['UNIT_TOLERANCE', 'DRIVER_HINT', 'pose_problem', 'InvalidPoses', 'no_transform_text',
           'invalid_update_text', 'invalid_odom_text']

#: A rotation whose squared length is further than this from 1 is not a unit quaternion: tf2's
#: own tolerance (BufferCore drops such a transform), so the course refuses what tf2 refuses.
UNIT_TOLERANCE = 0.01

#: The driver known to do it (turtlebot3_fake.cpp leaves its wheel separation unset then).
DRIVER_HINT = ('ROBOTIS\' turtlebot3_fake_node publishes NaN when its tb3_model parameter is '
               'not burger, waffle or waffle_pi; turtlebot3_fake.launch sets it from '
               'TURTLEBOT3_MODEL')


def _vector(values):
    return '(%s)' % ', '.join('%g' % v for v in values)


def pose_problem(position, rotation, velocity=None):
    """What makes a pose unusable, or None: a NaN or infinite ``position`` (x, y, z),
    ``rotation`` (x, y, z, w) or ``velocity`` (any sequence; None: not judged), else a
    rotation that is not a unit quaternion (within :data:`UNIT_TOLERANCE`)."""
    parts = [('position', position), ('rotation', rotation)]
    if velocity is not None:
        parts.append(('velocity', velocity))
    parts = [(name, tuple(float(v) for v in values)) for name, values in parts]
    bad = [(name, values) for name, values in parts
           if not all(math.isfinite(v) for v in values)]
    if bad:
        nan = any(math.isnan(v) for _, values in bad for v in values)
        return '%s in the %s' % ('NaN' if nan else 'infinity', ' and the '.join(
            '%s %s' % (name, _vector(values)) for name, values in bad))
    rotation = parts[1][1]
    length2 = sum(c * c for c in rotation)
    if abs(length2 - 1.0) > UNIT_TOLERANCE:
        return 'a rotation %s that is not a unit quaternion (length %.3g)' % (
            _vector(rotation), math.sqrt(length2))
    return None


class InvalidPoses(object):
    """The invalid poses heard, per node that published them: how many, and the latest fault."""

    def __init__(self):
        self.nodes = {}  # node -> [count, latest problem]

    def heard(self, node, problem):
        """Note one; True when it is the first from ``node``."""
        seen = self.nodes.get(node)
        if seen is None:
            self.nodes[node] = [1, problem]
            return True
        seen[0] += 1
        seen[1] = problem
        return False

    def __bool__(self):
        return bool(self.nodes)

    def count(self):
        return sum(count for count, _ in self.nodes.values())

    def names(self):
        """The nodes heard, in name order, comma-separated."""
        return ', '.join(sorted(self.nodes))

    def text(self):
        """The fault (the latest), or with several nodes, each one's count and fault."""
        if len(self.nodes) == 1:
            return next(iter(self.nodes.values()))[1]
        return '; '.join('%d from %s: %s' % (count, node, problem)
                         for node, (count, problem) in sorted(self.nodes.items()))


def no_transform_text(odom_frame, candidates, wait, invalid):
    """(problem, fix) when tf has no ``odom_frame`` -> any of ``candidates`` after ``wait`` s;
    ``invalid`` maps a candidate to the :class:`InvalidPoses` of it heard meanwhile."""
    heard = [(frame, invalid[frame]) for frame in candidates if invalid.get(frame)]
    if not heard:
        return ('no transform from %s to %s after %.1f s: nothing is publishing the robot\'s '
                'odometry on tf' % (odom_frame, ' or '.join(candidates), wait),
                'Start the robot first: roslaunch rbx1_nav fake_turtlebot.launch for the '
                'simulator, or the robot\'s driver (e.g. its bringup launch) on a real robot; or '
                'set ~odom_frame / ~base_frame to the frames your robot uses.')
    problem = '; '.join(
        'tf %s -> %s comes from %s, but all %d transforms of it in %.1f s were invalid (%s)' % (
            odom_frame, frame, poses.names(), poses.count(), wait, poses.text())
        for frame, poses in heard)
    nodes = sorted({node for _, poses in heard for node in poses.nodes})
    return (problem + ', and tf drops invalid transforms: the robot\'s driver is running but '
            'publishes a broken pose',
            'Fix %s (%s). The robot was not moved.' % (', '.join(nodes), DRIVER_HINT))


def invalid_update_text(parent, child, node, problem):
    """The error when ``parent -> child``, steered by, comes invalid from ``node`` mid-course."""
    return ('tf %s -> %s from %s is invalid (%s), and tf drops invalid transforms: the course '
            'has lost the robot\'s pose. Stopped the robot. Fix %s (%s).' % (
                parent, child, node, problem, node, DRIVER_HINT))


def invalid_odom_text(topic, node, problem):
    """The warning, once per node, when ``topic`` (nav_msgs/Odometry) comes invalid from it."""
    return ('%s from %s is invalid (%s): a fault in the robot\'s driver, %s. The course steers '
            'by tf; it counts the robot standing still by %s\'s velocities, skipping non-finite '
            'ones.' % (topic, node, problem, node, topic))
