"""A node started while one of its name is already up (no rospy here).

A second ``fake_turtlebot.launch`` (or a course's launch with ``sim:=true``
while the fake robot of another launch runs) would register its nodes
under the names the running ones hold; the master then shuts the running
ones down, and roscpp's robot_state_publisher takes the new one down with
it: no robot at all. Instead the new launch's nodes look first
(rbx1_nav.common.already_up_ros): the fake robot refuses with
:func:`refusal_text` and ends its launch; sim_clock, and
robot_state_publisher and RViz started through nodes/unless_running.py,
leave the running ones alone (:func:`skip_text`).
"""

__all__ = ['resolved_name', 'refusal_text', 'skip_text']


def resolved_name(argv, namespace, default):
    """The node's global name (``/robot1/fake_turtlebot``) from its command
    line ``argv`` (``__name:=``, ``__ns:=``), ``namespace`` (ROS_NAMESPACE)
    and its ``default`` name."""
    name = default
    for arg in argv:
        if arg.startswith('__name:='):
            name = arg[len('__name:='):]
        elif arg.startswith('__ns:='):
            namespace = arg[len('__ns:='):]
    parts = [part for part in (namespace or '').split('/') + [name] if part]
    return '/' + '/'.join(parts)


def refusal_text(name, pid):
    """The fake robot's line when ``name`` is held by a running process
    ``pid``: what runs, how to use it, how to start this one instead."""
    return ('a fake robot is already running as %s (pid %d, started by '
            'another launch or rosrun): this launch starts no second one and '
            'ends, leaving that robot as it is. To drive it, start the course '
            'without sim:=true (e.g. roslaunch rbx1_nav nav_square.launch) or '
            'with rosrun; to start this launch\'s robot instead, stop the '
            'running one first (Ctrl-C in its terminal, or rosnode kill %s)'
            % (name, pid, name))


def skip_text(name, pid):
    """A helper node's line when ``name`` is already held by ``pid``."""
    return ('%s is already running (pid %d): not starting a second one, '
            'which would shut it down' % (name, pid))
