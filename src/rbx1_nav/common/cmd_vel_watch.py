"""Two nodes driving one robot: the commonest real mistake.

``teleop_keyboard.py`` (or a joystick node, or a second course) left
running while a course drives: the robot jerks between the two streams of
commands. :class:`NewPublishers` is fed the publishers of a ``cmd_vel``
topic as the master lists them, every few seconds, and names each one
that needs a warning once: for a node that publishes there itself, every
other publisher; for the robot (``own`` None), every publisher once there
are two or more.

A publisher only warns: one that sends zeros (a teleop node at rest) or
nothing does no harm. :class:`OtherDriver` is what a course does about
one that *drives*: fed every message on its own cmd_vel with the node that
sent it, it remembers the first other node to command motion while the
course is armed (driving), so the course stops the robot and exits 1
naming it (:func:`other_driver_text`).
"""


class NewPublishers(object):
    """Which publishers of a topic to warn about, each once."""

    def __init__(self, own=None):
        self.own = own
        self.named = set()

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
        head = '%s also publish%s on %s' % (', '.join(new), 'es' * (len(new) == 1),
                                            topic)
    else:
        head = '%d nodes publish on %s: %s' % (len(others), topic, ', '.join(others))
    return ('%s; with two publishers the robot jerks between their commands. '
            'Stop the one you do not mean to drive (e.g. rosnode kill %s) or '
            'remap it to another topic' % (head, new[0]))


def is_motion(linear, angular):
    """True for a command that asks for any motion (NaN counts: it is not
    a stop). ``linear`` and ``angular`` are the Twist's two triples."""
    return any(value != 0.0 for value in tuple(linear) + tuple(angular))


class OtherDriver(object):
    """The first node other than ``own`` to command motion on a course's
    cmd_vel while the course is armed (:meth:`arm` .. :meth:`disarm`).

    Commands heard while disarmed (a calibration node waiting for its user,
    who drives the robot to its mark by hand) and stops (zero twists) from
    anyone are not a fight; the publisher watch warns of those.
    """

    def __init__(self, own):
        self.own = own
        self.armed = False
        self.found = None  # (node, linear x, angular z) of the first fight

    def arm(self):
        self.armed, self.found = True, None

    def disarm(self):
        self.armed = False

    def heard(self, caller, linear, angular):
        """A message on cmd_vel from ``caller``: its linear and angular
        (x, y, z) triples. True when it is the fight found."""
        if (not self.armed or self.found is not None or caller == self.own
                or not is_motion(linear, angular)):
            return False
        self.found = (caller, linear[0], angular[2])
        return True


def other_driver_text(topic, found):
    """The error when ``found`` (OtherDriver.found) drove the robot on
    ``topic`` during the course."""
    caller, linear, angular = found
    return ('%s commanded the robot on %s (%.3g m/s, %.3g rad/s) while this '
            'course drove it: two nodes driving one robot, the course cannot '
            'end where it should. Stopped the robot. Fix: stop the other '
            'node (rosnode kill %s) or remap one of them to another topic '
            '(cmd_vel:=...)' % (caller, topic, linear, angular, caller))
