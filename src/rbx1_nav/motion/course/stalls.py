"""Stalls: the spells the robot stood still while commanded to move (rospy-free)."""
import math

__all__ = ['Stalls']


class Stalls(object):
    """Spells of at least ``minimum`` s the robot stood still while its commands moved it (its
    watchdog on a lossy link, motors off, a bumper): every commanded speed (of the command
    ``in_flight`` says the robot ran) measured at under a tenth of itself. ``moved``: the stamp
    of the latest velocity over STILL (0.1 mm/s, 0.01 deg/s), None before."""

    STILL = (1e-4, 2e-4)  # m/s, rad/s

    def __init__(self, in_flight, minimum=0.1):
        self.in_flight, self.minimum = in_flight, minimum
        self.count, self.seconds = 0, 0.0
        self.since = None  # start of the current spell
        self.moved = None
        self.excused = -math.inf  # a spell counts from here on at the earliest

    def velocity(self, stamp, linear, angular):
        """Odometry's velocity at ``stamp`` (s); the length (s) of a spell it ended, else None."""
        if abs(linear) > self.STILL[0] or abs(angular) > self.STILL[1]:
            self.moved = max(stamp, self.moved or stamp)
        commanded = self.in_flight.command_at(stamp)
        pairs = [(abs(m), abs(c)) for m, c in ((linear, commanded.linear),
                                               (angular, commanded.angular)) if c]
        if pairs and all(measured < 0.1 * command for measured, command in pairs):
            if self.since is None:
                self.since = stamp
            return None
        return self.end(stamp)

    def excuse(self, until):
        """Standing still till ``until`` (s) is no spell: precise mode's Breakaway explains it."""
        self.excused = max(self.excused, until)

    def end(self, stamp):
        """Close a spell at ``stamp``; its length (s) if it counts, else None."""
        since, self.since = self.since, None
        if since is not None:
            since = max(since, self.excused)
        if since is None or stamp - since < self.minimum:
            return None
        self.count += 1
        self.seconds += stamp - since
        return stamp - since
