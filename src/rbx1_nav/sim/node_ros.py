"""The simulator nodes' entry points: :func:`fake_turtlebot` (one robot,
nodes/fake_turtlebot.py) and :func:`fake_fleet` (N robots in one process,
nodes/fake_fleet.py). Each is a :class:`Simulator`: the model
(rbx1_nav.sim.topics_ros.make_fleet), one RobotTopics per robot and the
fixed-rate loop (rbx1_nav.sim.loop_ros.spin_simulator).
"""
import threading

import rospy

from rbx1_nav.common.already_up_ros import refuse_if_running
from rbx1_nav.sim.loop_ros import spin_simulator
from rbx1_nav.sim.topics_ros import RobotTopics, make_fleet
from rbx1_nav.common.node_ros import forget_command_line, start_node, until_shutdown

__all__ = ['Simulator', 'fake_turtlebot', 'fake_fleet']


class Simulator:
    """The model of ``names`` robots (one RobotTopics each, made by
    ``topics(robot, values, lock, index, name)``) and the fixed-rate loop.
    Raises ValueError for a bad value, ImportError when ~physics finds no
    MuJoCo."""

    def __init__(self, values, names, topics, log_name):
        self.rate = values['rate']
        self.log_name = log_name
        self.sim = make_fleet(values, len(names), log_name)
        self.lock = threading.Lock()
        self.robots = [topics(self.sim.robot(i), values, self.lock, i, name)
                       for i, name in enumerate(names)]

    def spin(self):
        """Step every robot on a fixed grid of ROS times (under lockstep,
        also at their motion nodes' ticks) and publish each step: see
        rbx1_nav.sim.loop_ros.spin_simulator."""
        spin_simulator(self.rate, self.step, self.robots, self.log_name)

    def step(self, stamp, granted=True):
        """Advance every robot to ``stamp`` and publish their new states
        (all of them only at a ``granted`` step: rbx1_nav.sim.loop_ros._step_at)."""
        with self.lock:
            advanced = self.sim.step(stamp.to_sec())
        if advanced:
            for robot in self.robots:
                robot.publish(stamp, granted)


def _run(name, specs, doc, make):
    """Start the node ``name`` (``specs``, ``doc``: rbx1_nav.common.node_ros.start_node),
    make its Simulator (``make(values)``) and spin it until shutdown; the
    exit status: 1 for a bad value."""
    values = start_node(name, specs, doc)
    if values is None:
        return 1
    try:
        simulator = make(values)
    except (ValueError, ImportError) as err:
        rospy.logfatal('%s: %s', name, err)
        forget_command_line()
        return 1
    until_shutdown(simulator.spin)
    return 0


def fake_turtlebot(specs, doc):
    """nodes/fake_turtlebot.py: one robot, its topics relative to the
    node's namespace. With a fake robot of this name already running it
    refuses (rbx1_nav.common.already_up_ros) and returns 1."""
    if refuse_if_running('fake_turtlebot'):
        return 1

    def one_robot(robot, values, lock, index, name):
        return RobotTopics(robot, values, lock)

    return _run('fake_turtlebot', specs, doc,
         lambda values: Simulator(values, [None], one_robot, 'fake_turtlebot'))


def fake_fleet(specs, doc):
    """nodes/fake_fleet.py: one robot in each namespace of ~robots."""
    name = 'fake_fleet'

    def in_namespace(robot, values, lock, index, ns):
        return RobotTopics(robot, values, lock, ns=ns, index=index,
                           log_name='%s: %s' % (name, ns))

    def make(values):
        names = values['robots']
        fleet = Simulator(values, names, in_namespace, name)
        rospy.loginfo('%s: %d robots (%s), each with its tf on its own topic: '
                      '%s', name, len(names), ', '.join(names),
                      rospy.resolve_name(names[0] + '/tf'))
        return fleet

    return _run(name, specs, doc, make)
