"""Pacing of a simulation clock against the wall clock (for
rbx1_nav.sim_time.clock_ros, sim_clock.py's ROS side).

The clock advances simulated time in fixed steps of whole nanoseconds, so
stamps are exact multiples of the step, or straight to a time the lockstep
owner grants next (rbx1_nav.sim_time.lockstep: event-driven time), and schedules
each at ``speed`` times real time. When the publisher falls behind (a
starved CPU), it re-anchors instead of bursting to catch up: simulated
time then runs slower than asked. ``speed`` None runs unpaced: as fast as
the lockstep members allow. The wall time is passed in, so the pacing is
testable without sleeping.
"""
import math

from rbx1_nav.common.params import number

__all__ = ['ClockPacer', 'MIN_STEP', 'MAX_STEP', 'MIN_SPEED', 'MAX_SPEED',
           'MAX_START', 'speed']

MAX_STEP = 0.01  # s of simulated time per tick; nodes see time move smoothly
MIN_STEP = 1e-9  # s: one nanosecond, the resolution of ROS time
#: Bounds of the speed (x real time): slower would mean sleeps too long for
#: the OS, faster only spins the CPU.
MIN_SPEED, MAX_SPEED = 1e-3, 1e6
#: Latest start time (s): leaves rospy.Time's 32-bit seconds decades of room.
MAX_START = 2.0 ** 31


def speed(name, value):
    """A clock speed parameter: a number of x real time, or 'max' (None)."""
    if isinstance(value, str) and value.strip().lower() == 'max':
        return None
    try:
        return number(name, value, MIN_SPEED, MAX_SPEED)
    except ValueError:
        raise ValueError("%s must be 'max' or a number in [%g, %g], got %r"
                         % (name, MIN_SPEED, MAX_SPEED, value))


speed.none_text = 'max'  # how params.describe shows it


class ClockPacer:
    """Tick schedule for a clock running at ``speed`` x real time."""

    def __init__(self, speed, step=MAX_STEP, start=0.0, max_lag=0.1):
        if speed is not None and not (math.isfinite(speed)
                                      and MIN_SPEED <= speed <= MAX_SPEED):
            raise ValueError('sim speed must be in [%g, %g], got %r'
                             % (MIN_SPEED, MAX_SPEED, speed))
        if not (MIN_STEP <= step <= MAX_STEP):
            raise ValueError('clock step must be in [%g, %g] s, got %r'
                             % (MIN_STEP, MAX_STEP, step))
        if not (math.isfinite(start) and 0 <= start <= MAX_START):
            raise ValueError('start time must be in [0, %g] s, got %r' % (MAX_START, start))
        self.speed = None if speed is None else float(speed)
        self.step_ns = int(round(step * 1e9))
        self.max_lag = max_lag         # wall seconds behind before re-anchoring
        self.sim_ns = int(round(start * 1e9))
        self._anchor = None            # (wall seconds, sim ns) of the schedule

    def set_speed(self, speed):
        """Run at ``speed`` (None: unpaced) from the next step on."""
        if speed != self.speed:
            self.speed = speed
            self._anchor = None

    def advance(self, wall_now, target=None):
        """Move one step on, or to ``target`` (ns, later than now: the step
        the lockstep owner grants next); return (sim time in ns, wall
        seconds to wait). The caller waits the returned time, then
        publishes the sim time.
        """
        if self._anchor is None:
            self._anchor = (wall_now, self.sim_ns)
        if target is not None and target <= self.sim_ns:
            raise ValueError('clock target %d ns is not after %d ns'
                             % (target, self.sim_ns))
        self.sim_ns = self.sim_ns + self.step_ns if target is None else target
        if self.speed is None:
            return self.sim_ns, 0.0
        wall0, sim0 = self._anchor
        due = wall0 + (self.sim_ns - sim0) * 1e-9 / self.speed
        wait = due - wall_now
        if wait < -self.max_lag:
            self._anchor = (wall_now, self.sim_ns)
            wait = 0.0
        return self.sim_ns, max(wait, 0.0)
