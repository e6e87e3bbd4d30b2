"""The rospy-free half of motion.cmd_vel_ros: the hint when nothing takes a node's cmd_vel."""


def listener_hint(graph, own_node, own_topic):
    """Where ``own_node``'s commands on ``own_topic`` could go instead, from the master's ``graph``
    (common.master_ros.topic_graph(); None: master gone). ``own_node`` hears its own topic (a
    second driver), so no topic only it subscribes to is a driver's.
    """
    if graph is None:
        return 'is the robot driver running?'
    _, subscribers, types = graph
    topics = sorted(topic for topic, nodes in subscribers.items()
                    if types.get(topic) == 'geometry_msgs/Twist'
                    and topic != own_topic and set(nodes) - {own_node})
    if not topics:
        return 'no node takes geometry_msgs/Twist commands: is the robot driver running?'
    return ('these topics take Twist commands: %s. Remap to the driver\'s, '
            'e.g. cmd_vel:=%s' % (', '.join(topics), topics[0]))
