"""The runner's cmd_vel side: the publisher (the course's link's, told of each send), the wait for
the driver to subscribe, and other nodes driving the robot (heard on the topic itself): one that
drives during the course, or one already driving when it starts."""
import io

import rospy
from geometry_msgs.msg import Twist

from rbx1_nav.common.cmd_vel_watch import (COURSE_HEADER, OtherDriver, is_course,
                                           other_driver_text, refused_text)
from rbx1_nav.common.cmd_vel_watch_ros import heard_headers, kind_now, watch_publishers
from rbx1_nav.common.master_ros import topic_graph
from rbx1_nav.common.aborted import CourseAborted
from rbx1_nav.common.rospy_private_ros import (connection_header, connections,
                                              subscriber_name, unsent_bytes)
from rbx1_nav.motion.runner.deadline_ros import Deadline
from rbx1_nav.motion.runner.cmd_vel import listener_hint


class CmdVel(object):
    """The ``cmd_vel`` publisher of a course on ``link`` (a RobotLink)."""

    def __init__(self, link):
        self.link = link
        self.pub = link.publisher('cmd_vel', Twist, headers=dict([COURSE_HEADER]))
        self.own = rospy.get_name()
        self.others = OtherDriver(self.own)
        self.look = None  # a look at the other publishers (watch_publishers)
        # Heard from the start, so it is connected to whoever drives before this course would.
        self.sub = rospy.Subscriber(self.pub.resolved_name, Twist, self._on_cmd_vel,
                                    queue_size=100, tcp_nodelay=True)

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

    def watch_publishers(self, name):
        """Warn when another node publishes on this cmd_vel too (every few seconds; the first
        look by :meth:`hear_others`)."""
        self.look = watch_publishers(name, [self.pub.resolved_name], own=self.own, now=False)

    def _on_cmd_vel(self, msg):
        l, a = msg.linear, msg.angular
        header = connection_header(msg)
        self.others.heard(header.get('callerid', '?'), (l.x, l.y, l.z), (a.x, a.y, a.z),
                          is_course(header))

    def hear_others(self, wait):
        """The other nodes publishing on this cmd_vel, once this node hears each of them (up to
        ``wait`` wall s), named in a warning; from now on others.driving tells who drives."""
        graph = topic_graph()
        others = set(graph[0].get(self.pub.resolved_name, ())) - {self.own} if graph else set()
        deadline = Deadline(wait)
        while others - set(heard_headers(self.pub.resolved_name) or ()):
            if rospy.is_shutdown():
                raise rospy.ROSInterruptException('shutdown while waiting')
            if deadline.expired():
                break  # what it cannot hear it cannot judge; the course drives on
            deadline.poll(50)
        self.others.listen()
        if self.look is not None:
            self.look(graph)
        return others

    def refusal(self):
        """The error text when another node drove the robot since hear_others(), else None."""
        driving = self.others.driving
        if driving is None:
            return None
        return refused_text(self.pub.resolved_name, driving,
                            *kind_now(self.pub.resolved_name, driving[0]))

    def other_driver(self):
        """The error text when another node has commanded motion since others.arm(), else None."""
        found = self.others.found
        if found is None:
            return None
        return other_driver_text(self.pub.resolved_name, found,
                                 *kind_now(self.pub.resolved_name, found[0]))

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
