"""Every use of rospy's private names, in one place.

rospy's public API (rospy.* and the documented classes) has no way to do
what the functions below do. Each says why no public API serves and what
breaks if rospy changes the name; test/unit/test_rospy_private.py checks
that every name still exists in the installed rospy with the shape used
here, and that no other module of the package uses one.

Not here, as rospy documents them in its API reference, names them without
a leading underscore and other ROS packages use them:
``rospy.core.is_shutdown_requested`` (True while the shutdown hooks run,
before ``rospy.is_shutdown()`` turns true: no public function says that),
``rospy.rostime.wallsleep`` (time.sleep on Linux) and
``rospy.names.ns_join`` (rosgraph.names.ns_join).
"""
import fcntl
import struct
import termios

import rospy
import rospy.core
import rospy.impl.simtime
import rospy.rostime
from rospy.impl.masterslave import ROSHandler
from rospy.impl.registration import get_service_manager, get_topic_manager

__all__ = ['connection_header', 'sender', 'connections', 'subscribed_connections',
           'published_connections', 'publisher_name', 'subscriber_name',
           'transport_header', 'unsent_bytes', 'take_clock_subscriber',
           'set_rostime', 'shutdown_request_handler',
           'set_shutdown_request_handler', 'wait_for_shutdown', 'registrations']


def connection_header(msg):
    """The connection header dict of a message rospy delivered (callerid,
    topic, ...), one dict shared by every message of a connection and the
    same as its transport's (:func:`transport_header`). No public API names
    a message's sender (a Subscriber's callback_args cannot: one subscriber
    hears every publisher); if rospy stops setting ``_connection_header``
    this raises AttributeError in every callback that asks."""
    return msg._connection_header


def sender(msg):
    """The node that published ``msg`` (its connection header's callerid)."""
    return connection_header(msg)['callerid']


def connections(topic):
    """The connections (rospy transports) of a Publisher or Subscriber
    ``topic``. Publishers and Subscribers only count theirs
    (get_num_connections); if rospy drops ``impl.connections`` this raises
    AttributeError."""
    return list(topic.impl.connections)


def subscribed_connections(resolved_name):
    """The connections of this process's subscription to ``resolved_name``,
    whichever Subscriber made it; None if it has none. No public API finds a
    subscription by name; if rospy's topic manager changes this raises."""
    impl = get_topic_manager().get_subscriber_impl(resolved_name)
    return list(impl.connections) if impl else None


def published_connections(resolved_name):
    """The connections of this process's publication of ``resolved_name``;
    None if it has none. As :func:`subscribed_connections`."""
    impl = get_topic_manager().get_publisher_impl(resolved_name)
    return list(impl.connections) if impl else None


def publisher_name(connection):
    """The node at the publishing end of a subscriber's ``connection``.
    No public API names the publishers a subscriber is connected to; if
    rospy renames ``callerid_pub`` this raises AttributeError."""
    return connection.callerid_pub


def subscriber_name(connection):
    """The node at the subscribing end of a publisher's ``connection``.
    No public API names a publisher's subscribers; if rospy renames
    ``endpoint_id`` this raises AttributeError."""
    return connection.endpoint_id


def transport_header(connection):
    """The header dict of a subscriber's ``connection`` (None before it is
    read), the one its messages carry (:func:`connection_header`). No public
    API reaches it; if rospy renames ``header`` this raises AttributeError."""
    return connection.header


def unsent_bytes(connection):
    """Bytes a publisher's ``connection`` has not had acknowledged by the
    subscriber's host: in rospy's queue (a publisher with a queue_size) and
    in the kernel's send queue (Linux, TIOCOUTQ); 0 for a connection without
    a socket, None where it cannot be told (closed meanwhile, not Linux).
    No public API tells what a publisher has not yet delivered; if rospy
    renames ``_queue`` its queued bytes go uncounted, if ``socket``, the
    connection counts 0."""
    queued = sum(len(data) for data in getattr(connection, '_queue', None) or ())
    sock = getattr(connection, 'socket', None)
    if sock is None:
        return 0
    try:
        raw = fcntl.ioctl(sock.fileno(), termios.TIOCOUTQ, b'\0' * 4)
    except (OSError, ValueError):  # closed meanwhile, or not Linux
        return None
    return queued + struct.unpack('i', raw)[0]


def take_clock_subscriber():
    """Take rospy's own /clock Subscriber away from it and return it (None
    if it has none): the caller unregisters it and sets the time itself
    (:func:`set_rostime`). No public API stops rospy hearing /clock under
    /use_sim_time; if rospy renames ``_clock_sub`` this returns None and
    /clock goes on setting the time (slower, never wrong)."""
    sub = getattr(rospy.impl.simtime, '_clock_sub', None)
    if sub is not None:
        rospy.impl.simtime._clock_sub = None
    return sub


def set_rostime(stamp):
    """Set this process's ROS time to ``stamp``, as rospy's /clock callback
    does. No public API sets ROS time; if rospy renames ``_set_rostime``
    this raises AttributeError."""
    rospy.rostime._set_rostime(stamp)


def shutdown_request_handler():
    """The function answering the master's shutdown requests
    (ROSHandler.shutdown(self, caller_id, msg='')). No public API lets a
    node refuse one; if rospy moves it, importing this module fails."""
    return ROSHandler.shutdown


def set_shutdown_request_handler(handler):
    """Answer the master's shutdown requests with ``handler`` (same
    signature as :func:`shutdown_request_handler`'s)."""
    ROSHandler.shutdown = handler


def wait_for_shutdown():
    """Wait for a rospy shutdown under way to finish its hooks (rospy runs
    them holding ``_shutdown_lock``). rospy.signal_shutdown returns at once
    when one is under way, and no public API waits for it; if rospy renames
    the lock this raises AttributeError."""
    with rospy.core._shutdown_lock:
        pass


def registrations(timeout):
    """(publications, subscriptions, services) of this process as rospy
    keeps them: [(topic, type)], [(topic, type)], [(service, uri)]; None if
    rospy's topic list stays locked ``timeout`` s (a registration stuck on
    an unreachable master). No public API lists them; if rospy's managers
    change this raises."""
    topics = get_topic_manager()
    if not topics.lock.acquire(timeout=timeout):
        return None
    try:
        publications = topics.get_publications()
        subscriptions = topics.get_subscriptions()
    finally:
        topics.lock.release()
    return publications, subscriptions, get_service_manager().get_services()
