"""Throttle: say when a repeated warning may be logged again.

Shared by the nodes that warn about many things at once (one warning per
robot of a fleet, per sensor and kind of bad input): rospy's
``logwarn_throttle`` counts per line of code, so two robots or two sensors
warning from the same line would hold each other back. No rospy here.
"""

__all__ = ['Throttle']


class Throttle(object):
    """Once per ``period`` seconds per key.

    Times are seconds of ROS time; time moving backwards allows the warning
    again, as rospy's throttle does.
    """

    def __init__(self, period):
        self.period = period
        self.last = {}

    def ready(self, key, now):
        """True if the warning ``key`` may be logged at ``now`` (and note it)."""
        last = self.last.get(key)
        if last is None or now - last > self.period or now < last:
            self.last[key] = now
            return True
        return False
