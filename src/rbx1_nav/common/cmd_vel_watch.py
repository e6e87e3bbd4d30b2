"""Other nodes on a robot's cmd_vel. A second publisher only warns (it may send nothing); one that
drives during a course (:class:`OtherDriver`) has the course stop and exit 1; a course that finds
another already driving leaves the robot to it (:func:`refused_text`).

What to advise depends on what the other node is (:func:`kind_of`). A node that also subscribes to
the topic may be the driver's own process: turtlebot_bringup loads its velocity multiplexer as a
nodelet beside the Kobuki driver, so killing the publisher kills the driver. Only a node that
publishes and does not subscribe is offered a ``rosnode kill``, and another course only as a
choice."""

#: The connection header every course's cmd_vel publisher adds, so that other nodes tell a course
#: from a driver's multiplexer (both publish on the topic and subscribe to it).
COURSE_HEADER = ('rbx1_nav', 'course')

#: What another node on the topic is (kind_of); UNKNOWN when the master does not answer.
COURSE, DRIVER_PROCESS, PUBLISHER, UNKNOWN = 'course', 'driver process', 'publisher', 'unknown'

#: TurtleBot 2's multiplexer input for navigation: the remap when nothing better is known.
MUX_INPUT = '/cmd_vel_mux/input/navi'


def is_course(header):
    """True for a connection header (a dict) of a course's cmd_vel publisher."""
    key, value = COURSE_HEADER
    return bool(header) and header.get(key) == value


def kind_of(node, subscribers, courses):
    """COURSE, DRIVER_PROCESS (it takes the topic too: a driver, or a multiplexer in the driver's
    process) or PUBLISHER, for ``node`` among the topic's ``subscribers`` and known ``courses``."""
    if node in courses:
        return COURSE
    if node in subscribers:
        return DRIVER_PROCESS
    return PUBLISHER


def mux_input(node, graph_subscribers, types, topic):
    """The Twist input topic of ``node`` (a multiplexer) to remap a course to: the one named navi,
    else the first by name, from the master's subscribers by topic; MUX_INPUT if none."""
    inputs = sorted(other for other, nodes in graph_subscribers.items()
                    if other != topic and node in nodes
                    and types.get(other) == 'geometry_msgs/Twist')
    navi = [name for name in inputs if name.rstrip('/').endswith('navi')]
    return (navi or inputs or [MUX_INPUT])[0]


def advice(node, kind, remap_to):
    """What to do about ``node`` of ``kind`` (``remap_to``: its multiplexer input, for
    DRIVER_PROCESS)."""
    if kind == COURSE:
        return ('%s is another rbx1_nav course: a course does not start while another drives '
                'the robot' % node)
    if kind == DRIVER_PROCESS:
        return ('%s also takes this topic: most likely the robot\'s velocity multiplexer '
                '(cmd_vel_mux) loaded in the driver\'s own process (turtlebot_bringup\'s '
                'mobile_base_nodelet_manager), so do not stop it: that stops the driver. Drive '
                'through the multiplexer instead, e.g. cmd_vel:=%s' % (node, remap_to))
    if kind == PUBLISHER:
        return ('stop it if you do not mean it to drive (e.g. rosnode kill %s) or remap it to '
                'another topic' % node)
    return ('the master does not say whether %s also takes this topic (it may be the driver\'s '
            'own process): remap this course to another topic rather than stop it' % node)


class NewPublishers(object):
    """Which publishers of a topic to warn about, each once: every other one for a node that
    publishes there (``own``); for the robot (``own`` None), all once there are two or more."""

    def __init__(self, own=None):
        self.own, self.named = own, set()

    def update(self, publishers):
        """The publishers (node names) to name now, in name order."""
        others = set(publishers) - {self.own}
        if self.own is None and len(others) < 2:
            return []
        new = sorted(others - self.named)
        self.named |= others
        return new


def warning_text(topic, new, publishers, own=None, kinds=None):
    """The warning for ``new`` publishers among ``publishers`` of ``topic``; ``kinds``: node ->
    (kind, its multiplexer input) for the advice (unknown: PUBLISHER)."""
    kinds = kinds or {}
    others = sorted(set(publishers) - {own})
    if own is not None:
        head = '%s also publish%s on %s' % (', '.join(new), 'es' * (len(new) == 1), topic)
    else:
        head = '%d nodes publish on %s: %s' % (len(others), topic, ', '.join(others))
    tips = [advice(node, *kinds.get(node, (PUBLISHER, MUX_INPUT))) for node in new]
    return ('%s; with two publishers the robot jerks between their commands. %s'
            % (head, '; '.join(tips)))


def is_motion(linear, angular):
    """True for Twist triples asking for any motion (NaN too: it is not a stop)."""
    return any(value != 0.0 for value in tuple(linear) + tuple(angular))


class OtherDriver(object):
    """Other nodes' commands on a course's cmd_vel: the first node other than ``own`` to command
    motion while the course is armed (not while a calibration's user drives it to its mark by
    hand), and whether another node is driving the robot while the course listens before its
    first command (a course's commands, stops too, or anyone's motion)."""

    def __init__(self, own):
        self.own, self.armed = own, False
        self.found = None  # (node, linear x, angular z) of the first fight
        self.driving = None  # the same, of the first node heard driving since listen()

    def arm(self):
        self.armed, self.found = True, None

    def disarm(self):
        self.armed = False

    def listen(self):
        """Start hearing who drives the robot (before this course's first command)."""
        self.driving = None

    def heard(self, caller, linear, angular, course=False):
        """A cmd_vel message from ``caller`` (``course``: its publisher is a course's); True when
        it is the fight."""
        if caller == self.own:
            return False
        motion = is_motion(linear, angular)
        if self.driving is None and (course or motion):
            self.driving = (caller, linear[0], angular[2])
        if not self.armed or self.found is not None or not motion:
            return False
        self.found = (caller, linear[0], angular[2])
        return True


def other_driver_text(topic, found, kind=PUBLISHER, remap_to=MUX_INPUT):
    """The error when ``found`` (OtherDriver.found), a node of ``kind``, drove on ``topic``."""
    caller, linear, angular = found
    if kind == PUBLISHER:
        fix = ('stop the other node (rosnode kill %s) or remap one of them to another topic '
               '(cmd_vel:=...)' % caller)
    elif kind == COURSE:
        fix = 'run one course at a time; if %s is stale, stop it (rosnode kill %s)' % (
            caller, caller)
    else:
        fix = advice(caller, kind, remap_to)
    return ('%s commanded the robot on %s (%.3g m/s, %.3g rad/s) while this course drove it: two '
            'nodes driving one robot, the course cannot end where it should. Stopped the robot. '
            'Fix: %s' % (caller, topic, linear, angular, fix))


def refused_text(topic, driving, kind=PUBLISHER, remap_to=MUX_INPUT):
    """The error of a course that did not start: ``driving`` (OtherDriver.driving), a node of
    ``kind``, drives the robot on ``topic``."""
    caller, linear, angular = driving
    if kind == COURSE:
        choice = ('run this again when that course has ended; if it is stale (its terminal '
                  'gone), stop it first: rosnode kill %s' % caller)
    elif kind == DRIVER_PROCESS:
        choice = ('%s also takes the topic, most likely the robot\'s velocity multiplexer in '
                  'the driver\'s own process passing another input (teleop, navigation): do '
                  'not stop it. Stop what drives through it, and drive through the multiplexer, '
                  'e.g. cmd_vel:=%s' % (caller, remap_to))
    elif kind == PUBLISHER:
        choice = ('run this again when it has stopped; if it is stale, stop it first: '
                  'rosnode kill %s' % caller)
    else:
        choice = 'run this again when it has stopped (%s)' % advice(caller, kind, remap_to)
    return ('did not start: %s is driving the robot on %s (%.3g m/s, %.3g rad/s), so this course '
            'left the robot to it and sent nothing. %s' % (caller, topic, linear, angular,
                                                            choice[0].upper() + choice[1:]))
