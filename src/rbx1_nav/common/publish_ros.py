"""Publishing helpers shared by every node that keeps time under lockstep:
ROS times as integer nanoseconds, a message's connection, a publisher that
writes before publish() returns, a publish that is quiet once rospy shuts
down, and a node's ROS time kept by the node itself.
"""
import itertools
import warnings

import rospy

from rbx1_nav.common.rospy_private_ros import (connection_header, take_clock_subscriber,
                                              transport_header)

__all__ = ['from_ns', 'keep_own_time', 'link', 'publish',
           'synchronous_publisher', 'to_ns']


def to_ns(stamp):
    """rospy.Time -> integer nanoseconds."""
    return stamp.secs * 1000000000 + stamp.nsecs


def from_ns(ns):
    """Integer nanoseconds -> rospy.Time."""
    return rospy.Time(*divmod(int(ns), 1000000000))


_LINKS = itertools.count(1)
_LINK = '_rbx1_nav_link'


def link(msg):
    """A number for the connection ``msg`` came on, the same for every
    message on it and never given to another (rospy shares one header dict
    per connection: the number is kept there)."""
    header = connection_header(msg)
    number = header.get(_LINK)
    if number is None:
        number = header[_LINK] = next(_LINKS)
    return number


def delivered(connection):
    """True once a message that :func:`link` numbered came on
    ``connection`` (a subscriber's rospy transport): its publisher is
    writing to it."""
    return _LINK in (transport_header(connection) or {})


def synchronous_publisher(topic, msg_class, cls=rospy.Publisher, **kwargs):
    """A publisher (a ``cls``) that writes each message before publish()
    returns, with no Nagle delay: lockstep waits for every message, so a
    hand-off to rospy's queue thread would only add latency to each step."""
    with warnings.catch_warnings():  # queue_size None is the point here
        warnings.simplefilter('ignore', SyntaxWarning)
        return cls(topic, msg_class, queue_size=None, tcp_nodelay=True, **kwargs)


def publish(pub, msg):
    """Publish; False once rospy has closed its topics (shutting down)."""
    try:
        pub.publish(msg)
        return True
    except rospy.ROSException:
        if not rospy.core.is_shutdown_requested():
            raise
        return False


def keep_own_time():
    """Stop hearing /clock: from now on this node sets its ROS time itself
    (rbx1_nav.common.rospy_private_ros.set_rostime, what rospy's /clock
    callback calls).

    Under /use_sim_time rospy subscribes every node to /clock. The node
    that publishes it, and a simulator, granted every step /clock carries,
    know each time before /clock tells them; hearing it again costs the
    publisher a socket write and the node a thread woken, which takes the
    GIL from the stepping thread, at every step. True if rospy's /clock
    subscription was there and is gone (otherwise /clock still sets the
    time, and a node setting it too does no harm)."""
    sub = take_clock_subscriber()
    if sub is None:
        return False
    sub.unregister()
    return True
