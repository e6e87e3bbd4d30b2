"""The rospy-free half of the runner's cmd_vel side
(rbx1_nav.motion.cmd_vel_ros): the remap hint a motion node gives when
nothing takes its cmd_vel (the master's topic graph comes in, the text
goes out; cmd_vel_ros asks the master)."""


def listener_hint(graph, own_node, own_topic):
    """Where the velocity commands could go instead, from the master's
    ``graph`` (rbx1_nav.common.master_ros.topic_graph(); None when the
    master is gone).

    The node ``own_node`` publishes on ``own_topic``, which nothing else
    takes; the node also hears that topic itself (to notice a second
    driver), so neither it nor any topic only ``own_node`` subscribes to is
    a driver's.
    """
    if graph is None:  # the master is gone too: nothing to suggest
        return 'is the robot driver running?'
    _, subscribers, types = graph
    topics = sorted(topic for topic, nodes in subscribers.items()
                    if types.get(topic) == 'geometry_msgs/Twist'
                    and topic != own_topic and set(nodes) - {own_node})
    if not topics:
        return ('no node takes geometry_msgs/Twist commands: is the robot '
                'driver running?')
    return ('these topics take Twist commands: %s. Remap to the driver\'s, '
            'e.g. cmd_vel:=%s' % (', '.join(topics), topics[0]))
