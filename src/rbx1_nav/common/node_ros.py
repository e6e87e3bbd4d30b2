"""Start-up and shutdown shared by every node of the package.

:func:`start_node` answers ``--help`` without a master, says so while it
waits for one, starts rospy with signal handling that cannot deadlock,
keeps log calls off the master, waits for the first /clock under simulated
time, reads and checks the node's declared private parameters
(rbx1_nav.common.params.Param), refuses a private parameter it does not know
from its command line or launch file (a typo), warns about other unknown
ones (naming the nearest known one), logs the values it uses and names those
left on the parameter server by an earlier run (params.leftovers).
:func:`until_shutdown` runs a node's main loop; :func:`exit_node` is a
node's last line, and waits for the node to unregister while the master
answers. A node refuses a shutdown request the master meant for another
node (:func:`refuse_misdirected_shutdowns`).
"""
import os
import signal
import sys
import threading
import time

import rosgraph
import rospy

from rbx1_nav.common import params
from rbx1_nav.common.master_ros import master_identity
from rbx1_nav.common.master_watch import misdirected_text, replaced_node
from rbx1_nav.common.ros_time import no_clock_text
from rbx1_nav.common.rospy_private_ros import (set_shutdown_request_handler,
                                              shutdown_request_handler, wait_for_shutdown)


def _shutdown_on_signal(signum, frame):
    """A signal: shut rospy down from another thread.

    rospy's own handler calls signal_shutdown in the main thread, inside
    whatever that thread was doing. During a call to the master (a
    set_param, say) it then waits for the master connection's lock that the
    interrupted call holds, and the node hangs; during a publish, the
    shutdown hook's stop goes out first and the interrupted command after
    it. From a thread of its own, the shutdown waits for either to finish.
    """
    threading.Thread(target=rospy.signal_shutdown, daemon=True,
                     args=('signal %d' % signum,)).start()


def shut_down_on_signals(signums=(signal.SIGINT, signal.SIGTERM)):
    """Handle ``signums`` with :func:`_shutdown_on_signal`; before
    ``rospy.init_node(..., disable_signals=True)``."""
    for signum in signums:
        signal.signal(signum, _shutdown_on_signal)


def refuse_misdirected_shutdowns():
    """Refuse the master's shutdown request meant for another node.

    When a node starts under a name the master has on record, rosmaster
    sends the old node a shutdown request at the address it registered. If
    the old node ended without unregistering (killed, or gone while the
    master was slow to answer), another node may have been given its port
    since, and that node shuts down instead (ros/ros_comm#2241): a
    simulator given the port of an earlier calibration node would die as
    the next one started under that name. A request naming
    this node, and any other (``rosnode kill``), is obeyed as before.
    """
    obey = shutdown_request_handler()
    if getattr(obey, 'refuses_misdirected', False):
        return

    def shutdown(handler, caller_id, msg=''):
        meant = replaced_node(msg)
        if meant is not None and meant != rospy.get_name():
            rospy.logwarn(misdirected_text(rospy.get_name(), meant))
            return 1, 'not %s: refused' % meant, 0
        return obey(handler, caller_id, msg)

    shutdown.refuses_misdirected = True
    set_shutdown_request_handler(shutdown)


def exit_if_help(specs, doc):
    """Print usage (``doc``, the node's docstring, and ``specs``) and exit 0
    if the command line asks for help."""
    if any(arg in ('-h', '--help') for arg in sys.argv[1:]):
        from rbx1_nav.common.params_help import usage
        print(usage(doc, specs))
        raise SystemExit(0)


ROSOUT_SETTING = '/rosout_disable_topics_generation'


def cache_rosout_setting():
    """Keep log calls off the master.

    rospy's rosout handler reads ROSOUT_SETTING on every log call, and an
    unset parameter is never cached: each log line is a round trip to the
    master, slow when the master is busy (and a hang when it is gone). Set
    to rospy's own default, the value is cached after the first read.
    """
    if not rospy.has_param(ROSOUT_SETTING):
        rospy.set_param(ROSOUT_SETTING, False)


#: Wall seconds a node waits for the first /clock before it says that none comes.
CLOCK_WAIT = 5.0


def wait_for_clock(limit=CLOCK_WAIT):
    """Under /use_sim_time, wait up to ``limit`` wall seconds for the first
    /clock, so the start-up line and the node's start carry real stamps
    (ROS time is 0 until then). False if it did not come."""
    if not rospy.get_param('/use_sim_time', False):
        return True
    deadline = time.monotonic() + limit
    while (rospy.Time.now().is_zero() and time.monotonic() < deadline
           and not rospy.is_shutdown()):
        rospy.rostime.wallsleep(0.01)
    return not rospy.Time.now().is_zero()


def wait_for_master(name):
    """Say so, once, while there is no master; Ctrl-C exits with status 1."""
    if rosgraph.is_master_online():
        return
    sys.stderr.write('%s: waiting for the ROS master at %s: start roscore, or '
                     'check ROS_MASTER_URI (Ctrl-C to give up)\n'
                     % (name, rosgraph.get_master_uri()))
    try:
        while not rosgraph.is_master_online():
            rospy.rostime.wallsleep(0.5)
    except KeyboardInterrupt:
        raise SystemExit(1)


def read_params(specs):
    """Values of the node's private parameters ``specs``.

    Raises ValueError naming every unusable value and the command that
    clears each from the parameter server.
    """
    return params.check_all(
        specs, lambda name, default: rospy.get_param('~' + name, default),
        rospy.get_name())


def warn_unknown(name, specs):
    """One warning per private parameter on the server that no spec
    declares, left there by an earlier run; False, with one error instead,
    when one came from this node's command line or launch file (a typo:
    params.typos)."""
    given = rospy.get_param('~', {})
    found = params.unknown(given if isinstance(given, dict) else {}, specs)
    refused = params.typos(found, sys.argv)
    if refused:
        rospy.logerr('%s: %s', name, refused)
        return False
    for unknown, nearest in found:
        rospy.logwarn('%s: unknown parameter ~%s is ignored%s', name, unknown,
                      ' (did you mean ~%s?)' % nearest if nearest else '')
    return True


def start_node(name, specs, doc, clock=True):
    """--help (``doc`` and ``specs``), init_node, then read and log ``specs``.

    ``clock`` false skips the wait for the first /clock: for the node that
    publishes it.

    Returns the values, or None (logged, with how to clear a bad value) if
    any is unusable or a parameter given to the node is unknown.
    """
    exit_if_help(specs, doc)
    wait_for_master(name)
    shut_down_on_signals()
    refuse_misdirected_shutdowns()
    rospy.init_node(name, disable_signals=True)
    cache_rosout_setting()
    if clock and not wait_for_clock(CLOCK_WAIT):
        rospy.logwarn('%s: %s; waiting for it', name, no_clock_text(CLOCK_WAIT))
    if not warn_unknown(name, specs):
        return None
    try:
        values = read_params(specs)
    except ValueError as err:
        rospy.logerr('%s: bad parameters, not moving: %s', name, err)
        return None
    rospy.loginfo('%s: %s', name, params.start_text(specs, values))
    old = params.leftovers(specs, values, sys.argv, rospy.get_name())
    if old:
        rospy.logwarn('%s: %s', name, old)
    return values


def until_shutdown(loop):
    """Run a node's main ``loop``; a publish that shutdown closed under it
    (a signal shuts rospy down in another thread) ends it quietly."""
    try:
        loop()
    except rospy.ROSException:
        if not rospy.core.is_shutdown_requested():
            raise


#: Wall seconds rospy's shutdown (hooks, then unregistering from the
#: master) may take, unless the master answered meanwhile.
SHUTDOWN_LIMIT = 1.0
#: Wall seconds after which the node exits even though the master answers.
SHUTDOWN_BACKSTOP = 10.0


def _ask_master(timeout):
    """Ask the master who it is, in a thread of its own; return an Event
    set once it has answered (within ``timeout`` s)."""
    answered = threading.Event()

    def ask():
        try:
            master_identity(rosgraph.get_master_uri(), rospy.get_name(), timeout)
        except Exception:  # refused, timed out, reset: no answer
            return
        answered.set()

    threading.Thread(target=ask, daemon=True).start()
    return answered


def _shut_down(reason):
    """rospy's shutdown, or the end of the one already under way (a
    signal's, the master's request): rospy runs its hooks, unregistering
    from the master among them, holding its shutdown lock."""
    rospy.signal_shutdown(reason)
    wait_for_shutdown()


def exit_node(name, status):
    """Shut rospy down and exit with ``status`` (the last line of a node).

    Shutdown hooks run first (a motion node's stop goes out); rospy then
    unregisters from the master over a connection without a timeout, which
    hangs for minutes when the master is unreachable. A shutdown already
    under way (Ctrl-C's) is waited for too: a node that exits before it has
    unregistered stays on the master's record, and the next node of its
    name has the master send a shutdown to its old address, whichever node
    has that port by then (refuse_misdirected_shutdowns). So the node waits
    in rounds of SHUTDOWN_LIMIT wall seconds, asking the master who it is
    meanwhile: while the master answers, however busy, it waits on (up to
    SHUTDOWN_BACKSTOP); once a round passes without an answer (the link
    down, the master killed or hung) it exits without unregistering, and
    the master drops it when it next fails to reach it.
    """
    started = time.monotonic()
    done = threading.Thread(target=_shut_down, daemon=True,
                            args=('%s finished' % name,))
    done.start()
    while True:
        answered = _ask_master(SHUTDOWN_LIMIT)
        done.join(SHUTDOWN_LIMIT)
        if not done.is_alive():
            raise SystemExit(status)
        if not answered.is_set() or time.monotonic() - started > SHUTDOWN_BACKSTOP:
            sys.stderr.write('%s: the master at %s does not answer; exiting without '
                             'unregistering\n' % (name, rosgraph.get_master_uri()))
            sys.stderr.flush()
            os._exit(status)
