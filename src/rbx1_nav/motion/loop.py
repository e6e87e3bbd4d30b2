"""The pieces the runner's control loop (MotionRunner._drive) asks at each tick. No rospy:
times are ROS times (anything whose difference has ``to_sec()``), the log is passed in.
"""
from rbx1_nav.common.aborted import CourseAborted
from rbx1_nav.motion.dropouts import HOLD, LOST, Dropouts
from rbx1_nav.motion.settle import WAITING, delivered

__all__ = ['Reading', 'Hold', 'StallCheck', 'Settling']


class Reading(object):
    """The newest transform read: ``pose``, its ``stamp`` (None before the first), the tick
    ``fresh_at`` it came (or the first tick), and whether the last tick brought it (``fresh``)."""

    def __init__(self, pose=None):
        self.pose = pose
        self.stamp = self.fresh_at = None
        self.fresh = False

    def tick(self, now, reading):
        """Note what the tick at ``now`` read: (pose, stamp), or None."""
        if self.fresh_at is None:
            self.fresh_at = now
        self.fresh = reading is not None and (self.stamp is None or reading[1] > self.stamp)
        if self.fresh:
            self.pose, self.stamp = reading
            self.fresh_at = now

    def age(self, now):
        """Seconds from the transform's stamp to ``now``."""
        return (now - self.stamp).to_sec()


class Hold(object):
    """One course's ride through stale transforms (motion.dropouts): the robot held, or the
    course aborted past ~link_grace; ``where`` names the transform."""

    def __init__(self, name, where, timeout, grace, stop, warn, info):
        self.name, self.where, self.stop = name, where, stop
        self.warn, self.info = warn, info
        self.dropouts = Dropouts(timeout, grace)

    def held(self, now, reading):
        """True while the robot is to be held (commanded zero) at ``now``,
        by ``reading`` (a :class:`Reading`); CourseAborted when lost."""
        stamp = None if reading.stamp is None else reading.stamp.to_sec()
        tick = self.dropouts.tick(now.to_sec(), reading.fresh_at.to_sec(), stamp)
        if tick.state == LOST:
            self.stop()
            raise CourseAborted(
                '%s (limit ~tf_timeout %.2f s + ~link_grace %.2f s): robot driver or '
                'simulator gone, or the link to the robot down? Stopped the robot.' % (
                    self._stale(now, reading, tick), self.dropouts.timeout, self.dropouts.grace))
        if tick.began:
            self.warn('%s: %s (~tf_timeout): a link dropout? Holding the robot '
                      '(zero velocity) and waiting up to ~link_grace %.1f s for it'
                      % (self.name, self._stale(now, reading, tick), self.dropouts.grace))
        elif tick.ended is not None:
            self.info('%s: %s is back after %.2f s; carrying on from where it says '
                      'the robot is' % (self.name, self.where, tick.ended))
        return tick.state == HOLD

    def _stale(self, now, reading, tick):
        """How the transform is stale: not updated, or stamped long ago."""
        if reading.fresh_at == now:
            return ('%s is %.2f s old by its stamp though still arriving (a link holding messages '
                    'back, or the robot\'s clock behind this one\'s?)' % (self.where, tick.stale))
        return '%s has not been updated for %.2f s' % (self.where, tick.stale)

    def summary(self):
        """The dropouts ridden out, for the summary line."""
        return self.dropouts.summary()


class StallCheck(object):
    """Feeds the robot's measured velocities to a course's stall count, warning of each spell."""

    def __init__(self, name, warn):
        self.name, self.warn = name, warn

    def check(self, course, start, velocities):
        """``velocities``: (stamp, linear, angular) in stamp order; ``start``: the first tick."""
        for stamp, linear, angular in velocities:
            spell = course.stalls.velocity((stamp - start).to_sec(), linear, angular)
            if spell is not None:
                self.warn('%s: the robot stood still for %.2f s while commanded to move: '
                          'stopped by its watchdog (commands late or lost on the way to it?) '
                          'or held (motors off, bumper)' % (self.name, spell))


class Settling(object):
    """After the last step: the robot commanded zero at every tick until ``settle`` (a
    motion.settle.Settle) has a still robot or gives up; the stops sent are counted, so a command
    still on a slow link (more bytes unacknowledged than the stops') is no still robot."""

    def __init__(self, settle, message_bytes):
        self.settle, self.message_bytes = settle, message_bytes
        self.stops = 0

    def done(self, held, reading, start, unacknowledged):
        """After a stop sent: True once settled or given up; ``held``: the transform is stale
        (the wait, on odometry's stamps, pauses); ``unacknowledged``: bytes (None: unknown)."""
        self.stops += 1
        sent = delivered(unacknowledged, self.stops, self.message_bytes)
        return (not held and reading.fresh and self.settle.update(
            reading.pose, (reading.stamp - start).to_sec(), sent) != WAITING)

    @property
    def waiting(self):
        return self.settle.state == WAITING
