"""Another node publishing the transform this node publishes.

pose_ekf (``~publish_tf``) and the fake robot each listen on the tf topic
they publish on for their own child frame sent by another node: two
robots, or a driver and a filter, publishing one transform make every
robot's pose jump between them. :class:`OtherPublisherWatch` says when to
log it; :func:`robot_conflict_text` is the fake robot's line
(pose_ekf's is rbx1_nav.estimation.status.other_publisher_text). No rospy
here.
"""

__all__ = ['OtherPublisherWatch', 'robot_conflict_text', 'foreign_parent']


def foreign_parent(caller, own, transforms, child):
    """The parent frame of the first of ``transforms`` (a tf message's)
    with ``child`` as child frame, when ``caller`` (its sender) is not
    this node ``own``; else None."""
    if caller == own:
        return None
    for tf in transforms:
        if tf.child_frame_id.lstrip('/') == child:
            return tf.header.frame_id.lstrip('/')
    return None


class OtherPublisherWatch(object):
    """Spots another node publishing the transform this node publishes.

    :meth:`seen` is called for each tf message carrying our child frame
    from another node; it returns True when an error is due: at once for
    a new publisher, then every ``period`` seconds while it lasts.
    :meth:`gone` returns the publishers not heard for ``quiet`` seconds
    (each once), so the caller can say the conflict ended.
    """

    def __init__(self, period=30.0, quiet=5.0):
        self.period, self.quiet = float(period), float(quiet)
        self._last_seen = {}
        self._last_report = {}

    def seen(self, caller, now):
        self._last_seen[caller] = now
        last = self._last_report.get(caller)
        if last is None or now - last >= self.period or now < last:
            self._last_report[caller] = now
            return True
        return False

    def gone(self, now):
        ended = [c for c, t in self._last_seen.items() if now - t > self.quiet]
        for caller in ended:
            del self._last_seen[caller]
            self._last_report.pop(caller, None)
        return ended

    @property
    def publishers(self):
        """Other publishers heard within ``quiet`` s, in name order."""
        return sorted(self._last_seen)


def robot_conflict_text(caller, parent, child, topic):
    """The error a simulated robot logs while node ``caller`` also
    publishes its transform ``parent -> child`` on ``topic``."""
    return ('node %s also publishes the transform %s -> %s on %s; with two '
            'publishers every robot\'s pose jumps between them and a course '
            'steering by it stops. Fix: give each robot its own frames '
            '(_odom_frame:=robot1/odom _base_frame:=robot1/base_footprint, and '
            'the same for its course) or its own tf topic (/tf:=tf '
            '/tf_static:=tf_static for every node in its namespace), or stop '
            'the other one' % (caller, parent, child, topic))
