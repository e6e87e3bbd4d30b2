"""Two nodes driving one robot (a teleop left running), the commonest real mistake. A second
publisher only warns (it may send nothing); one that drives during a course
(:class:`OtherDriver`) has the course stop and exit 1."""


class NewPublishers(object):
    """Which publishers of a topic to warn about, each once: every other one for a node that
    publishes there (``own``); for the robot (``own`` None), all once there are two or more."""

    def __init__(self, own=None):
        self.own, self.named = own, set()

    def update(self, publishers):
        """The publishers (node names) to name now, in name order."""
        others = set(publishers) - {self.own}
        if self.own is None and len(others) < 2:
            return []
        new = sorted(others - self.named)
        self.named |= others
        return new


def warning_text(topic, new, publishers, own=None):
    """The warning for ``new`` publishers among ``publishers`` of ``topic``."""
    others = sorted(set(publishers) - {own})
    if own is not None:
        head = '%s also publish%s on %s' % (', '.join(new), 'es' * (len(new) == 1), topic)
    else:
        head = '%d nodes publish on %s: %s' % (len(others), topic, ', '.join(others))
    return ('%s; with two publishers the robot jerks between their commands. '
            'Stop the one you do not mean to drive (e.g. rosnode kill %s) or '
            'remap it to another topic' % (head, new[0]))


def is_motion(linear, angular):
    """True for Twist triples asking for any motion (NaN too: it is not a stop)."""
    return any(value != 0.0 for value in tuple(linear) + tuple(angular))


class OtherDriver(object):
    """The first node other than ``own`` to command motion while the course
    is armed (not while a calibration's user drives it to its mark by hand)."""

    def __init__(self, own):
        self.own, self.armed = own, False
        self.found = None  # (node, linear x, angular z) of the first fight

    def arm(self):
        self.armed, self.found = True, None

    def disarm(self):
        self.armed = False

    def heard(self, caller, linear, angular):
        """A cmd_vel message from ``caller``; True when it is the fight."""
        if (not self.armed or self.found is not None or caller == self.own
                or not is_motion(linear, angular)):
            return False
        self.found = (caller, linear[0], angular[2])
        return True


def other_driver_text(topic, found):
    """The error when ``found`` (OtherDriver.found) drove on ``topic``."""
    caller, linear, angular = found
    return ('%s commanded the robot on %s (%.3g m/s, %.3g rad/s) while this course drove it: two '
            'nodes driving one robot, the course cannot end where it should. Stopped the robot. '
            'Fix: stop the other node (rosnode kill %s) or remap one of them to another topic '
            '(cmd_vel:=...)' % (caller, topic, linear, angular, caller))
