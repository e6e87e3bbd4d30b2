"""A course's watch on a simulated /clock it does not own: the first one
awaited, a stopped one noticed. Loaded only under /use_sim_time
(rbx1_nav.entry.course_clock_ros).
"""
import threading
import time

import rospy

from rbx1_nav.common.aborted import CourseAborted
from rbx1_nav.common.node_ros import CLOCK_WAIT, wait_for_clock
from rbx1_nav.common.ros_time import no_clock_text


def require_clock(wait):
    """Under /use_sim_time, wait up to ``wait`` wall s more (after
    start_node's CLOCK_WAIT) for the first /clock; CourseAborted if none."""
    if not wait_for_clock(wait):
        if rospy.is_shutdown():
            raise rospy.ROSInterruptException('shutdown waiting for /clock')
        raise CourseAborted('giving up, the robot not moved: %s'
                            % no_clock_text(CLOCK_WAIT + wait))


class ClockWatchdog(object):
    """Under /use_sim_time, stop the robot and shut the node down when
    ROS time stands still for max(2 s, ``tf_timeout``) of wall time: with
    a dead clock rospy.Rate.sleep() blocks the control loop, and with it
    the stale-tf check, forever."""

    def __init__(self, name, tf_timeout, stop):
        self.name = name
        self.limit = max(2.0, tf_timeout)
        self.stop = stop

    def start(self):
        threading.Thread(target=self._watch, name='clock_watchdog', daemon=True).start()

    def _watch(self):
        last, since = rospy.get_rostime(), time.monotonic()
        while not rospy.is_shutdown():
            rospy.rostime.wallsleep(0.1)
            now = rospy.get_rostime()
            if now != last:
                last, since = now, time.monotonic()
            elif time.monotonic() - since > self.limit:
                self.stop()
                rospy.logerr('%s: /clock has not advanced for %.1f s of '
                             'wall time (simulator or clock node gone?); '
                             'stopped the robot', self.name, self.limit)
                rospy.signal_shutdown('simulated clock stopped')
                return


def watch_clock(name, wait, timeout, stop):
    """For a course ticking on a simulated /clock it does not own: wait up to ``wait`` s for
    the first /clock (CourseAborted if none), then stop the robot (``stop()``) and node ``name``
    if the clock stands still for max(2 s, ``timeout``)."""
    require_clock(wait)
    ClockWatchdog(name, timeout, stop).start()
