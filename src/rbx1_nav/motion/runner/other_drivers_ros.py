"""Other nodes driving the robot, heard on a course's own cmd_vel: one already driving when the
course starts (it leaves the robot to it), or one that commands motion during the course."""
import rospy
from geometry_msgs.msg import Twist

from rbx1_nav.common.cmd_vel_watch import OtherDriver, is_course, other_driver_text, refused_text
from rbx1_nav.common.cmd_vel_watch_ros import heard_headers, kind_now, watch_publishers
from rbx1_nav.common.master_ros import topic_graph
from rbx1_nav.common.rospy_private_ros import connection_header
from rbx1_nav.motion.runner.deadline_ros import Deadline


class OtherDrivers(object):
    """The other publishers on ``topic`` (the course's resolved cmd_vel), heard from the start,
    so this node is connected to whoever drives before its course would."""

    def __init__(self, topic):
        self.topic = topic
        self.own = rospy.get_name()
        self.others = OtherDriver(self.own)
        self.look = None  # a look at the other publishers (watch)
        self.sub = rospy.Subscriber(topic, Twist, self._on_cmd_vel,
                                    queue_size=100, tcp_nodelay=True)

    def arm(self):
        """From now on another node commanding motion is a fight (other_driver())."""
        self.others.arm()

    def disarm(self):
        self.others.disarm()

    def watch(self, name):
        """Warn when another node publishes on this cmd_vel too (every few seconds; the first
        look by :meth:`hear`)."""
        self.look = watch_publishers(name, [self.topic], own=self.own, now=False)

    def _on_cmd_vel(self, msg):
        l, a = msg.linear, msg.angular
        header = connection_header(msg)
        self.others.heard(header.get('callerid', '?'), (l.x, l.y, l.z), (a.x, a.y, a.z),
                          is_course(header))

    def hear(self, wait):
        """The other nodes publishing on this cmd_vel, once this node hears each of them (up to
        ``wait`` wall s), named in a warning; from now on refusal() tells who drove."""
        graph = topic_graph()
        others = set(graph[0].get(self.topic, ())) - {self.own} if graph else set()
        deadline = Deadline(wait)
        while others - set(heard_headers(self.topic) or ()):
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
        """The error text when another node drove the robot since hear(), else None."""
        driving = self.others.driving
        if driving is None:
            return None
        return refused_text(self.topic, driving,
                            *kind_now(self.topic, driving[0]))

    def other_driver(self):
        """The error text when another node has commanded motion since arm(), else None."""
        found = self.others.found
        if found is None:
            return None
        return other_driver_text(self.topic, found,
                                 *kind_now(self.topic, found[0]))
