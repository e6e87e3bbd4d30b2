"""The runner's cmd_vel side: the publisher (the course's link's, told of each send) and the wait
for the driver to subscribe. Other nodes on the same topic: other_drivers_ros."""
import io

import rospy
from geometry_msgs.msg import Twist

from rbx1_nav.common.cmd_vel_watch import COURSE_HEADER
from rbx1_nav.common.master_ros import topic_graph
from rbx1_nav.common.aborted import CourseAborted
from rbx1_nav.common.rospy_private_ros import connections, subscriber_name, unsent_bytes
from rbx1_nav.motion.runner.deadline_ros import Deadline
from rbx1_nav.motion.runner.cmd_vel import listener_hint


class CmdVel(object):
    """The ``cmd_vel`` publisher of a course on ``link`` (a RobotLink)."""

    def __init__(self, link):
        self.link = link
        self.pub = link.publisher('cmd_vel', Twist, headers=dict([COURSE_HEADER]))
        self.own = rospy.get_name()

    def _connections(self):
        """The publisher's connections, except the one to our own subscriber."""
        return [c for c in connections(self.pub) if subscriber_name(c) != self.own]

    @staticmethod
    def message_bytes():
        """Bytes one command takes on a connection (its length prefix too)."""
        buff = io.BytesIO()
        Twist().serialize(buff)
        return 4 + len(buff.getvalue())

    def unacknowledged(self):
        """The most command bytes a subscriber's host has not acknowledged (TCP delivers in order:
        older ones arrived), None if unknown; 0 when the link counts them (the robot waits)."""
        if self.link.counts_commands:
            return 0
        most = 0
        for conn in self._connections():
            unsent = unsent_bytes(conn)
            if unsent is None:
                return None
            most = max(most, unsent)
        return most

    def send(self, twist):
        """Publish on cmd_vel, and tell the link."""
        self.pub.publish(twist)
        self.link.sent(self.pub.resolved_name)

    def wait_for_listener(self, wait):
        """Wait up to ``wait`` wall s for the driver to subscribe: earlier commands are lost."""
        deadline = Deadline(wait)
        while True:
            connected = {subscriber_name(c) for c in self._connections()}
            if self.link.takers(connected):
                return
            if rospy.is_shutdown():
                raise rospy.ROSInterruptException('shutdown while waiting')
            if deadline.expired():
                refused = connected and self.link.not_taken(
                    self.pub.resolved_name, connected, wait)
                if refused:
                    raise CourseAborted(refused)
                raise CourseAborted('nothing subscribes to %s after %.1f s: %s' % (
                    self.pub.resolved_name, wait,
                    listener_hint(topic_graph(), self.own, self.pub.resolved_name)))
            deadline.poll(50)
