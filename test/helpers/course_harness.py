"""Shared plumbing for the out-and-back rostests (imported, not a node).

``CourseProcess`` starts a motion node (``odom_out_and_back.py`` by default)
as ``rosrun`` does (rosrun.node_path: the same executable, found once), so
a test sees its exit status and its log lines.
``FakeRobot`` starts the simulator with given parameters, for tests that
restart it. ``RobotWatch`` follows one robot's ``ground_truth`` (the simulator's true
pose) and ``cmd_vel`` (what the course commanded), optionally in a namespace.
Times are ROS times, so under /use_sim_time they are simulated seconds.
"""
import os
import re
import signal
import subprocess
import tempfile
import threading
import time

import rospkg
import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Log

from rbx1_nav.common.publish_ros import link
from rbx1_nav.motion.course.command import pose_error
from rbx1_nav.transform_utils import Pose2D, quat_to_angle
from rosrun import node_path

#: Wall seconds after which a wait for a live process gives up: a guard so
#: a hung run fails instead of hanging, never a verdict on a slow machine
#: (a wait for a process that has died fails at once, naming it).
WALL_LIMIT = 300.0
STILL = 1e-4  # m/s and rad/s: a robot slower than this is at rest


def _join(ns, name):
    return '%s/%s' % (ns, name) if ns else name


def is_zero(twist):
    """True if a Twist commands no motion at all."""
    return not any((twist.linear.x, twist.linear.y, twist.linear.z,
                    twist.angular.x, twist.angular.y, twist.angular.z))


class RobotWatch(object):
    """The latest true pose and every command of one (namespaced) robot,
    heard on ``cmd_vel``, the topic its driver takes."""

    def __init__(self, ns='', cmd_vel='cmd_vel'):
        self.ns = ns
        self.lock = threading.Lock()
        self.truth = None
        self.old_links = set()  # ground_truth connections of robots gone
        self.commands = []  # (ROS time received, Twist)
        rospy.Subscriber(_join(ns, 'ground_truth'), Odometry, self._on_truth)
        rospy.Subscriber(_join(ns, cmd_vel), Twist, self._on_cmd)

    def _on_truth(self, msg):
        with self.lock:
            if link(msg) not in self.old_links:
                self.truth = msg

    def forget_truth(self):
        """From now on only a new simulator's ground_truth counts (one
        started under the same name comes on a new connection)."""
        with self.lock:
            if self.truth is not None:
                self.old_links.add(link(self.truth))
            self.truth = None

    def _on_cmd(self, msg):
        with self.lock:
            self.commands.append((rospy.Time.now(), msg))

    def wait_for_truth(self, wall_limit=WALL_LIMIT, simulator=None):
        """Block until the simulator's first ground_truth arrives, however
        long it takes to start; fail at once if ``simulator`` (a
        :class:`FakeRobot`, if the test started it) has ended."""
        start = time.monotonic()
        alive = simulator.running if simulator else (lambda: True)
        wait_until(lambda: self.truth is not None or rospy.is_shutdown() or not alive(),
                   wall_limit)
        if self.truth is None:
            topic = _join(self.ns, 'ground_truth')
            if not alive():
                raise AssertionError('no %s received: the simulator ended (exit %s) '
                                     'before it published. %s'
                                     % (topic, simulator.proc.returncode, simulator.tail()))
            raise AssertionError('no %s received in %.0f s (wall): is the simulator up?'
                                 % (topic, time.monotonic() - start))
        return self.pose()

    def pose(self):
        """The true pose now, as a Pose2D."""
        with self.lock:
            p = self.truth.pose.pose
        return Pose2D(p.position.x, p.position.y, quat_to_angle(p.orientation))

    def true_speed(self):
        """(linear, angular) speed of the simulated robot now."""
        with self.lock:
            t = self.truth.twist.twist
        return t.linear.x, t.angular.z

    def still(self, speed=STILL):
        """True while the simulated robot moves slower than ``speed`` (m/s
        and rad/s alike)."""
        return all(abs(value) < speed for value in self.true_speed())

    def moved_since(self, start):
        """Metres between the true pose now and ``start``."""
        return pose_error(self.pose(), start)[0]

    def motion_commands(self):
        """The cmd_vel messages that asked for motion."""
        with self.lock:
            return [(t, m) for t, m in self.commands if not is_zero(m)]

    def last_command(self):
        with self.lock:
            return self.commands[-1] if self.commands else (None, None)


class TopicLog(object):
    """Every message on ``topic``, as ``keep(msg)`` makes it, in order of
    arrival: ``records`` (under ``lock``), or a copy from :meth:`snapshot`."""

    def __init__(self, topic, msg_type, keep=lambda msg: msg):
        self.lock = threading.Lock()
        self.records = []
        self.keep = keep
        rospy.Subscriber(topic, msg_type, self._on_msg)

    def _on_msg(self, msg):
        item = self.keep(msg)
        with self.lock:
            self.records.append(item)

    def snapshot(self):
        with self.lock:
            return list(self.records)


class RosoutWatch(TopicLog):
    """Log lines that nodes send to /rosout, with their ROS time stamps."""

    def __init__(self):
        TopicLog.__init__(self, '/rosout', Log)

    def find(self, node, text):
        """The first Log from ``node`` (resolved name) containing ``text``."""
        with self.lock:
            for msg in self.records:
                if msg.name == node and text in msg.msg:
                    return msg
        return None

    def all(self, node, text):
        """Every Log from ``node`` containing ``text``, in order."""
        with self.lock:
            return [msg for msg in self.records
                    if msg.name == node and text in msg.msg]

    def stamp_of(self, node, text, wall_limit=WALL_LIMIT):
        """ROS time of that line, waiting for it to arrive; None if never."""
        found = []
        wait_until(lambda: found.append(self.find(node, text)) or found[-1],
                   wall_limit)
        return found[-1].header.stamp if found[-1] else None


class CourseProcess(object):
    """A motion node (odom_out_and_back.py unless ``script`` says otherwise)
    run as rosrun runs it, its output collected; ``remaps`` maps topic names
    (``{'/tf': 'tf'}``) as ``from:=to`` on its command line; ``leftovers``
    are private parameters set on the master, not on its command line, as
    an earlier run leaves them."""

    def __init__(self, ns='', params=None, name=None,
                 script='odom_out_and_back.py', remaps=None, leftovers=None):
        name = name or script[:-len('.py')]
        args = [node_path(script), '__name:=' + name]
        self.node_name = '/' + _join(ns.strip('/'), name)
        if ns:
            args.append('__ns:=' + ns)
        for key, value in sorted((params or {}).items()):
            # rospy reads each value as YAML: an empty one would be null
            # (the parameter's default), not the empty string.
            args.append('_%s:=%s' % (key, "''" if value == '' else value))
        args.extend('%s:=%s' % pair for pair in sorted((remaps or {}).items()))
        self.args = args
        if self.node_name == rospy.get_name():
            raise AssertionError('the node under test would take the test '
                                 'node\'s name %s: rename the test' % self.node_name)
        # Private parameters of an earlier run stay on the master; start clean.
        if rospy.has_param(self.node_name):
            rospy.delete_param(self.node_name)
        for key, value in sorted((leftovers or {}).items()):
            rospy.set_param(self.node_name + '/' + key, value)
        self.lines = []
        self.line_times = []  # wall time (time.monotonic) each line arrived
        self.exit_time = None
        self.start_time = rospy.Time.now()
        # Unbuffered, so each line arrives (and is timed) when it is logged.
        self.proc = subprocess.Popen(args, env=dict(os.environ, PYTHONUNBUFFERED='1'),
                                     stdout=subprocess.PIPE,
                                     stderr=subprocess.STDOUT,
                                     universal_newlines=True)
        self.reader = threading.Thread(target=self._read)
        self.reader.daemon = True
        self.reader.start()

    def _read(self):
        for line in self.proc.stdout:
            self.line_times.append(time.monotonic())
            self.lines.append(line.rstrip())

    def wall_time_of(self, text):
        """Wall time (time.monotonic) the first line with ``text`` arrived."""
        for line, when in zip(self.lines, self.line_times):
            if text in line:
                return when
        return None

    @property
    def output(self):
        return '\n'.join(self.lines)

    def running(self):
        return self.proc.poll() is None

    def ended(self):
        """True once the node has closed its output (it exited) and every
        line of it has been read."""
        return not self.reader.is_alive()

    def wait(self, wall_limit=WALL_LIMIT):
        """Wait for the node to exit; note the ROS time; return its status."""
        start = time.monotonic()
        if not wait_until(lambda: self.proc.poll() is not None, wall_limit):
            self.proc.kill()
            self.proc.wait()
            raise AssertionError('%s still running after %.0f s wall (a hang guard); '
                                 'killed.\n%s' % (' '.join(self.args),
                                                   time.monotonic() - start, self.output))
        self.exit_time = rospy.Time.now()
        self.reader.join(5.0)
        return self.proc.returncode

    def finish(self, wall_limit=WALL_LIMIT):
        """:meth:`wait`, then :meth:`cleanup` whatever happened; the status."""
        try:
            return self.wait(wall_limit)
        finally:
            self.cleanup()

    def interrupt(self):
        """Ctrl-C, as a user at the terminal would."""
        self.proc.send_signal(signal.SIGINT)

    def cleanup(self):
        """Kill the node if a failed test left it running."""
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()


class FakeRobot(object):
    """fake_turtlebot.py as rosrun runs it, with the given private parameters."""

    def __init__(self, settings):
        rospy.set_param('/fake_turtlebot', settings)
        # Its output kept beside the run's other logs, so a robot that
        # exits early (leaving lockstep before a course began) says why.
        self.log = tempfile.NamedTemporaryFile(
            prefix='fake_turtlebot_', suffix='.log', delete=False,
            dir=rospkg.get_log_dir() if os.path.isdir(rospkg.get_log_dir()) else None)
        self.proc = subprocess.Popen([node_path('fake_turtlebot.py')],
                                     stdout=self.log, stderr=subprocess.STDOUT)

    def running(self):
        return self.proc.poll() is None

    def tail(self, lines=20):
        """The end of its output, to say why it ended."""
        self.log.flush()
        with open(self.log.name) as f:
            text = f.read().splitlines()[-lines:]
        return 'The end of its log (%s):\n%s' % (self.log.name, '\n'.join(text))

    def close(self):
        self.proc.terminate()
        self.proc.wait()
        self.log.close()
        if rospy.has_param('/fake_turtlebot'):
            rospy.delete_param('/fake_turtlebot')

    @staticmethod
    def restart(robot, watch, settings):
        """Close ``robot`` (or None), start one with ``settings``, wait for
        its first ground truth (it has joined the lockstep, if any); return
        the new robot. An earlier robot's ground truth does not count,
        whether closed here or before (a population lane's robots come one
        after another): a course started on it would begin before the new
        robot took part, at a tick that depends on the machine's load."""
        if robot:
            robot.close()
        watch.forget_truth()
        robot = FakeRobot(settings)
        try:
            watch.wait_for_truth(simulator=robot)
        except BaseException:
            robot.close()  # no simulator outlives the test that started it
            raise
        return robot


#: The line a calibration node prints its correction in.
CORRECTION = re.compile(r'(odom_(?:linear|angular)_scale_correction) = '
                        r'measured / odometry = \S+ / \S+ = (\S+)')


def calibrate(test, kind, wall_limit=WALL_LIMIT, **params):
    """Run calibrate_<kind>.py once with ground_truth as the tape measure,
    stop it with Ctrl-C as a user does; assert it printed its correction
    (within ``wall_limit`` wall seconds, a guard against a hang) and exited
    0. Returns (the correction, the node's output)."""
    node = CourseProcess(script='calibrate_%s.py' % kind, params=dict(
        {'start_test': 'true', 'ground_truth_topic': 'ground_truth',
         'tf_timeout': 5.0}, **params))
    try:
        found = []
        ended = wait_until(lambda: found.extend(CORRECTION.findall(node.output))
                           or found or node.ended(), wall_limit=wall_limit)
        test.assertTrue(found, 'no correction printed (%s):\n%s' % (
            'the node ended' if ended else 'in %.0f s, wall' % wall_limit,
            node.output))
        node.interrupt()
        test.assertEqual(node.wait(wall_limit), 0, node.output)
    finally:
        node.cleanup()
    name, value = found[0]
    test.assertEqual(name, 'odom_%s_scale_correction' % kind)
    return float(value), node.output


def course_end_error(test, watch, script='odom_out_and_back.py', rest=0.5,
                     wall_limit=WALL_LIMIT, **params):
    """Run ``script`` with ``params`` to its end (asserting exit 0 within
    ``wall_limit`` wall seconds, a guard against a hang), let the robot
    rest ``rest`` simulated seconds; return the true distance (m) and
    heading change (deg, absolute) from its start."""
    import math
    # The node before may have ended with its last stop still in flight:
    # the start is where the robot comes to rest, not wherever it was
    # when the wall clock got here.
    test.assertTrue(wait_until(watch.still, wall_limit), 'the robot is still moving '
                    'at %s before the course' % (watch.true_speed(),))
    start = watch.pose()
    node = CourseProcess(script=script, params=dict({'tf_timeout': 5.0}, **params))
    try:
        test.assertEqual(node.wait(wall_limit), 0, node.output)
    finally:
        node.cleanup()
    wait_sim(rest)
    end = watch.pose()
    return (math.hypot(end.x - start.x, end.y - start.y),
            math.degrees(abs(math.remainder(end.yaw - start.yaw, 2 * math.pi))))


def wait_sim(seconds):
    """Sleep in ROS time (simulated under /use_sim_time)."""
    rospy.sleep(rospy.Duration(seconds))


def wait_until(predicate, wall_limit=WALL_LIMIT):
    """Poll ``predicate`` until true; False if it never was within
    ``wall_limit`` wall seconds."""
    deadline = time.monotonic() + wall_limit
    while not predicate():
        if time.monotonic() > deadline:
            return False
        rospy.rostime.wallsleep(0.01)
    return True


#: Wall seconds between two questions to the master while a node runs: a
#: loop paced in simulated time would ask hundreds of times a wall second
#: at full speed, and the master (rostest's own process) answers each.
MASTER_POLL = 0.1


def node_registered(master, node):
    """True while ``node`` has a publication or subscription on ``master``
    (a rosgraph.Master)."""
    publishers, subscribers, _ = master.getSystemState()
    return any(node in nodes for _, nodes in publishers + subscribers)


def kill_node(name):
    """Shut node ``name`` down as ``rosnode kill`` does, from this process:
    a new ``rosnode`` process takes about a second to start on a loaded
    machine, in which a course at full speed can end."""
    import rosnode
    killed, failed = rosnode.kill_nodes([name])
    if failed or not killed:
        raise RuntimeError('could not kill %s' % name)


def wait_under_way(test, watch, start, course, also=lambda: True, distance=0.3):
    """Wait until the robot is ``distance`` m from ``start`` (and ``also()``
    holds), with the course still running; assert both."""
    test.assertTrue(wait_until(lambda: (watch.moved_since(start) > distance
                                        and also()) or not course.running()),
                    'robot never moved')
    test.assertTrue(course.running(), course.output)


#: rostest's log file. Its children inherit the variable, and rospy.init_node
#: points it at the node's own log file: read it at import, before that.
ROSTEST_LOG = os.environ.get('ROS_LOG_FILENAME')


def launched_node_status(process, wall_limit=WALL_LIMIT):
    """Exit status and log of a node the .test file launched (rostest only).

    ``process`` is roslaunch's name for it without the trailing count
    (``raw/odom_out_and_back`` for a node of that name in group raw).
    rostest logs to its file (:data:`ROSTEST_LOG`) where it started the
    node, with the node's own log file (``__log:=``), and how the node
    ended, once its process monitor saw it end. Waits up to ``wall_limit`` wall seconds for that line; returns
    (exit status, None if it is still running, or 'died without exit
    code'; the text of the node's log file). A log file, not /rosout:
    rospy can drop a node's last /rosout lines when it exits right after
    them.
    """
    name = re.escape(process) + r'-\d+'
    started = re.compile(r"process\[(%s)\]: start w/ args .*'__log:=([^']+)'" % name)
    ended = re.compile(r'\[(%s)\] process has (finished cleanly|died)'
                       r'(?: \[pid \d+, exit code (-?\d+))?' % name)
    found = {}

    def read():
        with open(ROSTEST_LOG) as f:
            text = f.read()
        found['start'] = started.search(text)
        found['end'] = ended.search(text)
        return found['end']

    wait_until(read, wall_limit)
    if found['start'] is None:
        raise AssertionError('no process %s in %s' % (process, ROSTEST_LOG))
    with open(found['start'].group(2)) as f:
        log = f.read()
    end = found['end']
    if end is None:
        return None, log
    if end.group(2) == 'finished cleanly':
        return 0, log
    return (int(end.group(3)) if end.group(3) else 'died without exit code'), log


def check_completed_course(test, watch, course, start, expected_end=None,
                           tolerances=None):
    """Assert the course exited 0 and left the robot stopped near its goal.

    ``tolerances`` (m, deg), by default the test's private parameters
    ~position_tolerance and ~heading_tolerance. Returns the
    (position error m, heading error deg) measured on ground_truth.
    """
    import math
    if tolerances is None:
        tolerances = (rospy.get_param('~position_tolerance'),
                      rospy.get_param('~heading_tolerance'))
    position_tolerance, heading_tolerance = (float(value) for value in tolerances)
    status = course.wait()
    test.assertEqual(status, 0, 'course exited %s:\n%s' % (status, course.output))
    test.assertIn('Course complete', course.output)
    wait_sim(0.5)  # let the last stop reach the simulator
    dist, heading = pose_error(watch.pose(), expected_end or start)
    heading = math.degrees(heading)
    rospy.loginfo('%s: final true pose error %.1f mm, %.2f deg (limits %.1f mm, '
                  '%.2f deg)', watch.ns or 'robot', 1000 * dist, heading,
                  1000 * position_tolerance, heading_tolerance)
    print('RESULT %s position_error_mm=%.2f heading_error_deg=%.3f'
          % (watch.ns or 'robot', 1000 * dist, heading))
    why = '\nnode output:\n' + course.output
    test.assertLess(dist, position_tolerance, why)
    test.assertLess(abs(heading), heading_tolerance, why)
    test.assertEqual(watch.true_speed(), (0.0, 0.0), 'robot still moving')
    stamp, last = watch.last_command()
    test.assertTrue(last is not None and is_zero(last),
                    'last cmd_vel was not a stop: %s' % last)
    return dist, heading
