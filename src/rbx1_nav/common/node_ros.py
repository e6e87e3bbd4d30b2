"""Every node's start-up and shutdown: start_node, until_shutdown, exit_node; a node that refuses
to start after start_node calls forget_command_line."""
import atexit
import os
import signal
import sys
import threading
import time

import rosgraph
import rospy

from rbx1_nav.common import params, params_given
from rbx1_nav.common.master_ros import master_identity
from rbx1_nav.common.master_watch import misdirected_text, replaced_node
from rbx1_nav.common.ros_time import no_clock_text
from rbx1_nav.common.rospy_private_ros import (end_xmlrpc_loop_at_shutdown,
                                              set_shutdown_request_handler,
                                              shutdown_hooks_done, shutdown_request_handler)


def _shutdown_on_signal(signum, frame):
    """Shut rospy down from another thread. rospy's own handler runs it inside whatever call
    the main thread is in: a hang in a call to the master (its lock held), and, in a
    publish, the shutdown hook's stop sent before the command being published."""
    threading.Thread(target=rospy.signal_shutdown, daemon=True,
                     args=('signal %d' % signum,)).start()


def shut_down_on_signals(signums=(signal.SIGINT, signal.SIGTERM)):
    """Handle ``signums`` with :func:`_shutdown_on_signal` (init_node's disable_signals)."""
    for signum in signums:
        signal.signal(signum, _shutdown_on_signal)


def refuse_misdirected_shutdowns():
    """Refuse the master's shutdown meant for another node: a new node of a
    name has it sent to the old one's address, whichever node got that port
    since the old one ended unregistered (ros/ros_comm#2241)."""
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


def mend_rospy_shutdown():
    """Before init_node: refuse a shutdown meant for another node, and end
    the XML-RPC loop rospy leaves spinning at shutdown (ros/ros_comm#2238)."""
    refuse_misdirected_shutdowns()
    end_xmlrpc_loop_at_shutdown()


def exit_if_help(specs, doc):
    """Print usage (``doc``, the node's docstring, and ``specs``) and exit 0 on --help."""
    if any(arg in ('-h', '--help') for arg in sys.argv[1:]):
        from rbx1_nav.common.params_help import usage
        print(usage(doc, specs))
        raise SystemExit(0)


ROSOUT_SETTING = '/rosout_disable_topics_generation'


def cache_rosout_setting():
    """Keep log calls off the master: rospy reads ROSOUT_SETTING on each log call until it is set
    (a round trip per line, a hang with the master gone); set it to rospy's own default."""
    if not rospy.has_param(ROSOUT_SETTING):
        rospy.set_param(ROSOUT_SETTING, False)


#: Wall seconds a node waits for the first /clock before it says that none comes.
CLOCK_WAIT = 5.0


def wait_for_clock(limit=CLOCK_WAIT):
    """Under /use_sim_time, wait up to ``limit`` wall s for a /clock; False if none."""
    if not rospy.get_param('/use_sim_time', False):
        return True
    deadline = time.monotonic() + limit
    while (rospy.Time.now().is_zero() and time.monotonic() < deadline and not rospy.is_shutdown()):
        rospy.rostime.wallsleep(0.01)
    return not rospy.Time.now().is_zero()


def wait_for_master(name):
    """Say so, once, while there is no master. Ctrl-C ends the node: at once
    in this package's nodes (their first line gives SIGINT its default
    action), with status 1 where Python's KeyboardInterrupt is in place."""
    if rosgraph.is_master_online():
        return
    sys.stderr.write('%s: waiting for the ROS master at %s: start roscore, or check ROS_MASTER_URI '
                     '(Ctrl-C to give up)\n' % (name, rosgraph.get_master_uri()))
    try:
        while not rosgraph.is_master_online():
            rospy.rostime.wallsleep(0.5)
    except KeyboardInterrupt:
        raise SystemExit(1)


def warn_unknown(name, specs, given):
    """Warn of unknown private parameters among ``given`` (names); False (logged) if a typo."""
    found = params.unknown(given, specs)
    refused = params.typos(found, sys.argv)
    if refused:
        rospy.logerr('%s: %s', name, refused)
        return False
    for unknown, nearest in found:
        rospy.logwarn('%s: unknown parameter ~%s is ignored%s', name, unknown,
                      ' (did you mean ~%s?)' % nearest if nearest else '')
    return True


def init_node(name):
    """rospy.init_node without the command line's private parameters (common.params_given), with
    this package's signal handling; False if a shutdown (a signal: roslaunch ending the launch,
    Ctrl-C; or the master) came during it, which rospy raises as ROSInitException: the node then
    ends quietly, never having started.

    Before this, a node file sets SIGINT to its default action as its first line, so that a
    signal while Python imports it ends it without a KeyboardInterrupt traceback;
    shut_down_on_signals takes over from that."""
    try:
        rospy.init_node(name, disable_signals=True, argv=[
            arg for arg in sys.argv if params_given.private_name(arg) is None])
    except rospy.ROSInitException:
        if rospy.core.is_shutdown_requested():
            return False
        raise
    return True


def private_params():
    """(the command line's private parameters, as rospy reads them; the master's namespace)."""
    before = rospy.get_param('~', {})
    return (rospy.client.load_command_line_node_params(sys.argv),
            before if isinstance(before, dict) else {})


_PUT_BACK = []  # what keep_command_line replaced: (names to delete, {name: old value})


def keep_command_line(given, before):
    """The node starts: set ``given`` on the master as init_node does (later runs and dynparam
    read them there), remembering what they replaced in ``before``."""
    for key, value in given.items():
        rospy.set_param('~' + key, value)
    _PUT_BACK[:] = [params_given.put_back(before, given)]


def forget_command_line():
    """A node refusing to start after start_node: put back what keep_command_line replaced."""
    for deletes, restores in _PUT_BACK:
        for key in deletes:
            try:
                rospy.delete_param('~' + key)
            except KeyError:  # gone already
                pass
        for key, value in restores.items():
            rospy.set_param('~' + key, value)
    del _PUT_BACK[:]


def start_node(name, specs, doc, clock=True):
    """--help (``doc`` and ``specs``), init_node, then read and log ``specs``;
    ``clock`` false (the node that publishes it) skips waiting for /clock.
    Returns the values, or None (logged) if one is unusable or unknown: then
    the command line's ``_name:=value`` are not on the master (init_node); or
    None (quietly) if the node was stopped while it started."""
    exit_if_help(specs, doc)
    wait_for_master(name)
    shut_down_on_signals()
    mend_rospy_shutdown()
    if not init_node(name):
        return None
    cache_rosout_setting()
    if clock and not wait_for_clock(CLOCK_WAIT):
        rospy.logwarn('%s: %s; waiting for it', name, no_clock_text(CLOCK_WAIT))
    try:
        given, before = private_params()
        if not warn_unknown(name, specs, set(before) | {key.split('/')[0] for key in given}):
            return None
        values = params.check_all(specs, params_given.layered(given, before), rospy.get_name(),
                                  given)
    except (ValueError, rospy.ROSInitException) as err:
        rospy.logerr('%s: bad parameters, not moving: %s', name, err)
        return None
    keep_command_line(given, before)
    rospy.loginfo('%s: %s', name, params.start_text(specs, values))
    old = params.leftovers(specs, values, sys.argv, rospy.get_name())
    if old:
        rospy.logwarn('%s: %s', name, old)
    return values


def until_shutdown(loop):
    """Run a node's main ``loop``; a publish a shutdown closed under it ends it quietly."""
    try:
        loop()
    except rospy.ROSException:
        if not rospy.core.is_shutdown_requested():
            raise


#: Wall seconds rospy's shutdown may take, unless the master answered meanwhile.
SHUTDOWN_LIMIT = 1.0
#: Wall seconds after which the node exits even though the master answers.
SHUTDOWN_BACKSTOP = 10.0


def _ask_master(timeout):
    """An Event set once the master answers (within ``timeout`` s)."""
    answered = threading.Event()

    def ask():
        try:
            master_identity(rosgraph.get_master_uri(), rospy.get_name(), timeout)
        except Exception:  # refused, timed out, reset: no answer
            return
        answered.set()

    threading.Thread(target=ask, daemon=True).start()
    return answered


def _exit_now(status):
    """Exit with ``status`` as SystemExit does, less the interpreter's teardown of every module
    (0.15 s, a launch's end waits for it): atexit's functions run (logging's flush among them),
    then stdout's and stderr's. With a thread that is no daemon still running, SystemExit, which
    waits for it."""
    if not isinstance(status, int) or any(
            not thread.daemon for thread in threading.enumerate()
            if thread is not threading.main_thread()):
        raise SystemExit(status)
    atexit._run_exitfuncs()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)


def exit_node(name, status):
    """Shut rospy down and exit with ``status`` (a node's last line), once its hooks have run.
    rospy unregisters without a timeout, a hang with the master unreachable, yet a node that exits
    unregistered stays on record (refuse_misdirected_shutdowns): so wait while the master
    answers, up to SHUTDOWN_BACKSTOP."""
    started = time.monotonic()
    threading.Thread(target=rospy.signal_shutdown, daemon=True,
                     args=('%s finished' % name,)).start()
    while True:
        answered = _ask_master(SHUTDOWN_LIMIT)
        if shutdown_hooks_done(SHUTDOWN_LIMIT):
            _exit_now(status)
        if not answered.is_set() or time.monotonic() - started > SHUTDOWN_BACKSTOP:
            sys.stderr.write('%s: the master at %s does not answer; exiting without '
                             'unregistering\n' % (name, rosgraph.get_master_uri()))
            sys.stderr.flush()
            os._exit(status)
