"""Two nodes driving one robot: the commonest real mistake.

``teleop_keyboard.py`` (or a joystick node, or a second course) left
running while a course drives: the robot jerks between the two streams of
commands. :class:`NewPublishers` is fed the publishers of a ``cmd_vel``
topic as the master lists them, every few seconds, and names each one
that needs a warning once: for a node that publishes there itself, every
other publisher; for the robot (``own`` None), every publisher once there
are two or more.
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
