"""ROS time that never came or moved backwards: texts and a watch. No rospy."""

__all__ = ['ClockWatch', 'no_clock_text', 'time_moved_back_text']


def no_clock_text(waited):
    """What to do when no /clock came under /use_sim_time for ``waited`` wall s."""
    return ('/use_sim_time is true but nothing publishes /clock after %.1f s: a launch with '
            'sim_speed:=N (or sim_clock.launch) publishes it; for real time, `rosparam set '
            '/use_sim_time false` and start this again (left true by a launch with sim_speed '
            'that was killed, or by rosparam set)' % waited)


class ClockWatch(object):
    """Notices ROS time moving backwards between two calls of :meth:`moved_back`."""

    def __init__(self):
        self.last = None

    def moved_back(self, now):
        """Seconds ROS time went back since the previous call (0.0 if not)."""
        last, self.last = self.last, now
        return 0.0 if last is None or now >= last else last - now


def time_moved_back_text(seconds, then='Restarting from the next readings'):
    """A node's log line when ROS time moved back, ``then`` what it does."""
    return ('ROS time moved backwards by %.1f s: a bag looping or the '
            'simulator restarted? %s' % (seconds, then))
