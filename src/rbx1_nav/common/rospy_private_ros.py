"""Every use of rospy's private names, each checked by test_rospy_private.py.
Not here, as rospy documents them: ``rospy.core.is_shutdown_requested`` (True while shutdown
hooks run), ``rospy.rostime.wallsleep`` and ``rospy.names.ns_join``."""
import fcntl
import struct
import termios
import threading
import time

import rospy
import rospy.core
import rospy.impl.simtime
import rospy.rostime
import rosgraph.xmlrpc
from rospy.impl.masterslave import ROSHandler
from rospy.impl.registration import get_service_manager, get_topic_manager

__all__ = ['connection_header', 'sender', 'connections', 'subscribed_connections',
           'published_connections', 'publisher_name', 'subscriber_name', 'transport_header',
           'unsent_bytes', 'limit_send_wait', 'take_clock_subscriber', 'set_rostime', 'shutdown_request_handler',
           'set_shutdown_request_handler', 'shutdown_hooks_done',
           'registrations', 'end_xmlrpc_loop_at_shutdown']


def connection_header(msg):
    """The connection header (callerid, topic, ...) of a message rospy delivered,
    which no public API gives; without ``_connection_header`` this raises."""
    return msg._connection_header


def sender(msg):
    """The node that published ``msg`` (its connection header's callerid)."""
    return connection_header(msg)['callerid']


def connections(topic):
    """The connections (transports) of a Publisher or Subscriber ``topic``,
    which only count them publicly; without ``impl.connections`` this raises."""
    return list(topic.impl.connections)


def subscribed_connections(resolved_name):
    """The connections of this process's subscription to ``resolved_name`` or
    None; no public API finds one by name (a changed topic manager raises)."""
    impl = get_topic_manager().get_subscriber_impl(resolved_name)
    return list(impl.connections) if impl else None


def published_connections(resolved_name):
    """As :func:`subscribed_connections`, for this process's publication of that topic."""
    impl = get_topic_manager().get_publisher_impl(resolved_name)
    return list(impl.connections) if impl else None


def publisher_name(connection):
    """The node at the publishing end of a subscriber's ``connection``, which
    no public API names; without ``callerid_pub`` this raises."""
    return connection.callerid_pub


def subscriber_name(connection):
    """The node at the subscribing end of a publisher's ``connection``, which
    no public API names; without ``endpoint_id`` this raises."""
    return connection.endpoint_id


def transport_header(connection):
    """The header dict of a subscriber's ``connection`` (None before it is
    read), which no public API reaches; without ``header`` this raises."""
    return connection.header


def unsent_bytes(connection):
    """Bytes a publisher's ``connection`` has not had acknowledged (rospy's queue
    and the kernel's), 0 without a socket, None if unknown; no public API tells
    (renamed, ``_queue`` or ``socket`` counts 0)."""
    queued = sum(len(data) for data in getattr(connection, '_queue', None) or ())
    sock = getattr(connection, 'socket', None)
    if sock is None:
        return 0
    try:
        raw = fcntl.ioctl(sock.fileno(), termios.TIOCOUTQ, b'\0' * 4)
    except (OSError, ValueError):  # closed meanwhile, or not Linux
        return None
    return queued + struct.unpack('i', raw)[0]


def limit_send_wait(connection, seconds):
    """Let a write to a publisher's ``connection`` wait at most ``seconds`` (no public API sets
    it); rospy drops a connection whose write times out, as a broken one."""
    sock = getattr(connection, 'socket', None)
    if sock is not None and sock.gettimeout() is None:
        sock.settimeout(seconds)


def take_clock_subscriber():
    """Take rospy's own /clock Subscriber from it (None if none), for the
    caller to unregister and :func:`set_rostime` itself. No public API does;
    without ``_clock_sub``, /clock goes on setting the time (slower, never wrong)."""
    sub = getattr(rospy.impl.simtime, '_clock_sub', None)
    if sub is not None:
        rospy.impl.simtime._clock_sub = None
    return sub


def set_rostime(stamp):
    """Set ROS time to ``stamp`` as rospy's /clock callback does; no public API can."""
    rospy.rostime._set_rostime(stamp)


def shutdown_request_handler():
    """ROSHandler.shutdown(self, caller_id, msg=''): no public API lets a node
    refuse the master's shutdown; if rospy moves it, this import fails."""
    return ROSHandler.shutdown


def set_shutdown_request_handler(handler):
    """Answer the master's shutdown requests with ``handler``, shaped as ROSHandler.shutdown."""
    ROSHandler.shutdown = handler


def shutdown_hooks_done(timeout):
    """True once a shutdown has run its hooks (unregistering among them), within ``timeout`` s.
    No public API waits for them; signal_shutdown returns 0.6 s after them (it joins rospy's
    registration thread, which polls every 0.5 s, then sleeps 0.1 s)."""
    deadline = time.monotonic() + timeout
    while not rospy.core.is_shutdown():  # set under the lock, before the hooks
        if time.monotonic() >= deadline:
            return False
        rospy.rostime.wallsleep(0.002)  # shutdown is wall-timed: no /clock then
    if not rospy.core._shutdown_lock.acquire(timeout=max(0.0, deadline - time.monotonic())):
        return False
    rospy.core._shutdown_lock.release()
    return True


def registrations(timeout):
    """([(topic, type)], [(topic, type)], [(service, uri)]) of this process, which
    no public API lists; None if rospy's topic list stays locked ``timeout`` s."""
    topics = get_topic_manager()
    if not topics.lock.acquire(timeout=timeout):
        return None
    try:
        publications, subscriptions = topics.get_publications(), topics.get_subscriptions()
    finally:
        topics.lock.release()
    return publications, subscriptions, get_service_manager().get_services()


def end_xmlrpc_loop_at_shutdown():
    """rospy's shutdown closes its XML-RPC socket and leaves serve_forever() spinning a core
    until the process exits (ros/ros_comm#2238, unfixed in Noetic); no public API reaches
    that server, so XmlRpcNode.shutdown is wrapped to end the loop (in a thread: it may wait
    on a reused descriptor up to 0.5 s). Raises at start-up if rosgraph renames them."""
    shutdown = rosgraph.xmlrpc.XmlRpcNode.shutdown
    if getattr(shutdown, 'ends_loop', False):
        return

    def shutdown_and_end_loop(node, reason):
        server = node.server
        shutdown(node, reason)
        if server is not None:
            threading.Thread(target=server.shutdown, name='xmlrpc_end', daemon=True).start()

    shutdown_and_end_loop.ends_loop = True
    rosgraph.xmlrpc.XmlRpcNode.shutdown = shutdown_and_end_loop
