"""The ROS side of calibrate_linear.py and calibrate_angular.py.

Like the book's nodes, each is a dynamic_reconfigure server that waits for
``start_test``; setting it (from rqt_reconfigure where installed, with
``rosrun dynamic_reconfigure dynparam set``, or ``_start_test:=true`` on the
command line) runs one test through rbx1_nav.motion.runner.runner_ros, then clears it.
The node then needs the distance or angle really covered: from
``~ground_truth_topic`` (nav_msgs/Odometry, e.g. the simulator's
ground_truth) when set, otherwise from the ``measured_*`` field the user
sets after measuring the floor (a value typed while the test still runs is
kept and used when it ends: rbx1_nav.calibration.scale.Answers). It prints
the scale correction to set on the driver (rbx1_nav.calibration.scale) and
waits for the next test.

A test that fails (no tf, a stale transform, the clock gone, Ctrl-C) stops
the robot and ends the node with status 1; Ctrl-C between tests ends it
with status 0.
"""
import threading

import rospy
from dynamic_reconfigure.server import Server

from rbx1_nav.calibration import scale
from rbx1_nav.common import params
from rbx1_nav.common.params import param
from rbx1_nav.common.node_ros import start_node
from rbx1_nav.motion.runner.runner_params import common_params
from rbx1_nav.motion.runner.runner_ros import MotionRunner, guarded
from rbx1_nav.calibration.truth_ros import TRUTH_PARAM, GroundTruth

NODE_PARAMS = (
    TRUTH_PARAM,
    param('settle', 1.0, params.number, 's',
          'stopped time before odometry is read', minimum=0.0, maximum=60.0),
)


def config_params(config_type):
    """The reconfigure fields of ``config_type`` as Params, with its bounds.

    So they are checked at start-up like every other parameter:
    dynamic_reconfigure itself would clamp an out-of-range number silently
    and choke on a string.
    """
    specs = []
    for field in config_type.config_description['parameters']:
        name = field['name']
        if field['type'] == 'bool':
            specs.append(param(name, field['default'], params.flag, '',
                               field['description']))
        else:
            # A measured_* field lets dynamic_reconfigure pass a negative
            # value on, for the node to refuse aloud (its minimum would
            # clamp it to 0, "not measured", in silence); at start-up it is
            # not a measurement yet, and must be 0 or more.
            minimum = (max(field['min'], 0.0) if name.startswith('measured_')
                       else field['min'])
            specs.append(param(name, field['default'], params.number, '',
                               field['description'], minimum=minimum,
                               maximum=field['max']))
    return tuple(specs)


class CalibrationNode(object):
    """One calibration kind's tests, between reconfigure and the runner."""

    def __init__(self, kind, config_type, settings, choose_clock):
        self.kind = kind
        self.name = 'calibrate_' + kind.name
        self.settings = settings
        self.runner = MotionRunner(self.name, settings, choose_clock)
        self.lock = threading.Lock()
        self.config = None
        self.odometry = None  # the last test's odometry value, kind's unit
        self.node_factor = 1.0  # and the node's correction field it ran with
        self.answers = scale.Answers(kind, rospy.get_name())
        topic = settings['ground_truth_topic']
        self.truth = GroundTruth(topic) if topic else None
        self.server = Server(config_type, self.on_reconfigure)

    def on_reconfigure(self, config, level):
        with self.lock:
            note = self.answers.reconfigured(config)
            self.config = config
        if note:
            (rospy.logwarn if note[0] == 'warn' else rospy.loginfo)(
                '%s: %s', self.name, note[1])
        return config

    def spin(self):
        """Serve tests until shutdown; raises if a test fails."""
        self.runner.start()
        with self.lock:
            starting = self.config['start_test']
        if starting:  # _start_test:=true on the command line
            rospy.loginfo('%s: ready; starting the test at once (start_test true)',
                          self.name)
        else:
            rospy.loginfo('%s: ready. Start a test with: rosrun dynamic_reconfigure '
                          'dynparam set %s start_test true', self.name,
                          rospy.get_name())
        poll = rospy.Rate(10)
        while not rospy.is_shutdown():
            with self.lock:
                config = dict(self.config)
                measured = self.answers.take()
            if measured:  # for the last test, even if the next one starts now
                self.report(measured, 'measured on the floor')
            if config['start_test']:
                reported = self.run_test(config)
                with self.lock:
                    early = self.answers.take()  # typed while the test ran
                try:
                    self.server.update_configuration({'start_test': False})
                except rospy.ROSException:
                    if rospy.core.is_shutdown_requested():
                        break  # Ctrl-C after the test: the robot is stopped
                    raise
                if early:
                    rospy.loginfo('%s: using %s %g, given while the test ran',
                                  self.name, self.kind.measured, early)
                    self.report(early, 'measured on the floor')
                elif not reported:
                    rospy.loginfo(
                        '%s: now measure the %s the robot really %s and give it '
                        '(%s): rosrun dynamic_reconfigure dynparam set %s %s VALUE',
                        self.name, self.kind.quantity, self.kind.moved,
                        self.kind.unit_name, rospy.get_name(), self.kind.measured)
            try:
                poll.sleep()
            except rospy.ROSInterruptException:
                break

    def run_test(self, config):
        """One test; True if ground truth gave its measurement."""
        kind = self.kind
        course = scale.course(kind, config, self.settings['settle'])
        rospy.loginfo('%s: %s %g %s at %g %s, tolerance %g %s, this node\'s '
                      '%s %g', self.name, kind.goal, config[kind.goal],
                      kind.unit, config['speed'], kind.speed_unit,
                      config['tolerance'], kind.unit, kind.correction,
                      config[kind.correction])
        if self.truth:  # the robot stands still until the course's first tick
            self.truth.start(rospy.Time.now())
        final = self.runner.run(course)
        self.odometry = scale.measure(kind, course.start_pose, final,
                                            course.yaw_total)
        self.node_factor = config[kind.correction]
        rospy.loginfo('%s: odometry says %.4f %s (tf %s -> %s, robot settled)',
                      self.name, self.odometry, kind.unit,
                      self.runner.odom_frame, self.runner.followed)
        truth = self.truth.stop(self.runner.last_tick) if self.truth else None
        if truth is None:
            return False
        self.report(truth.value(kind), 'ground truth on %s' % self.truth.topic)
        return True

    def report(self, measured, source):
        if self.odometry is None:
            rospy.logwarn('%s: %s %g given before any test; run a test first '
                          '(start_test true)', self.name, self.kind.measured,
                          measured)
            return
        try:
            lines, warning = scale.report(self.kind, self.odometry,
                                                measured, source,
                                                self.node_factor)
        except ValueError as err:
            rospy.logwarn('%s: %s; no correction computed', self.name, err)
            return
        for line in lines:
            rospy.loginfo('%s: %s', self.name, line)
        if warning:
            rospy.logwarn('%s: %s', self.name, warning)


def node_params(config_type):
    """Every parameter of a calibration node with ``config_type``."""
    return config_params(config_type) + NODE_PARAMS + common_params(rate=20.0)


def main(kind, config_type, specs, choose_clock, doc):
    """main() of calibrate_<kind>.py (``specs``: its parameters,
    :func:`node_params`; ``choose_clock``: the runner's, MotionRunner;
    ``doc``: its docstring, for --help); returns the exit status."""
    name = 'calibrate_' + kind.name
    values = start_node(name, specs, doc)
    if values is None:
        return 1
    node = CalibrationNode(kind, config_type, values, choose_clock)
    return guarded(name, node.runner, node.spin)
