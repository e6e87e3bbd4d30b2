"""The bag side of plot_course.py: read the pose tracks a bag holds and
plot them with rbx1_nav.motion.plot.course_plot (the plotting, without rosbag).
No ROS master is needed.
"""
import argparse
import os
import sys

import rosbag

from rbx1_nav.motion.plot.course_plot import (Track, describe_error,
                                         describe_final_offset, plot_course)
from rbx1_nav.transform_utils import quat_to_angle


def read_tracks(bag_path, topics):
    """One Track per (name, topic) pair, from the pose messages in a bag.

    Any message with ``pose.pose`` works: nav_msgs/Odometry and
    geometry_msgs/PoseWithCovarianceStamped.
    """
    wanted = dict((topic.strip('/'), Track(name)) for name, topic in topics)
    with rosbag.Bag(bag_path) as bag:
        # Bags store names as recorded: '/odom', or 'odom' if given relative.
        names = [t for t in bag.get_type_and_topic_info().topics
                 if t.strip('/') in wanted]
        for topic, msg, _ in bag.read_messages(topics=names):
            pose = msg.pose.pose
            wanted[topic.strip('/')].add(pose.position.x, pose.position.y,
                                         quat_to_angle(pose.orientation))
    return [wanted[topic.strip('/')] for _, topic in topics]


def main(doc, argv=None):
    parser = argparse.ArgumentParser(description=doc.split('\n')[0])
    parser.add_argument('bag', help='bag file with nav_msgs/Odometry topics')
    parser.add_argument('-o', '--output',
                        help='PNG to write (default: the bag name with .png)')
    parser.add_argument('--odom-topic', default='odom')
    parser.add_argument('--truth-topic', default='ground_truth',
                        help='true pose topic; skipped if not in the bag')
    parser.add_argument('--fused-topic', default='robot_pose_ekf/odom_combined',
                        help='fused pose topic (pose_ekf); skipped if not in '
                        'the bag')
    args = parser.parse_args(argv)
    output = args.output or os.path.splitext(args.bag)[0] + '.png'
    try:
        odom, truth, fused = read_tracks(args.bag, [
            ('odom', args.odom_topic), ('ground truth', args.truth_topic),
            ('fused', args.fused_topic)])
    except (IOError, OSError, rosbag.ROSBagException) as err:
        print('plot_course: cannot read %s: %s' % (args.bag, err), file=sys.stderr)
        return 1
    if not len(odom):
        print('plot_course: no nav_msgs/Odometry on %s in %s' % (
            args.odom_topic, args.bag), file=sys.stderr)
        return 1
    tracks = [odom, truth, fused]
    plot_course(tracks, output, title=os.path.basename(args.bag),
                reference=truth if len(truth) else None)
    print('plot_course: wrote %s; end vs start: %s' % (output, '; '.join(
        describe_error(t) for t in tracks if len(t))))
    if len(truth):
        print('plot_course: final distance from the truth: %s' % '; '.join(
            describe_final_offset(t, truth) for t in (odom, fused) if len(t)))
    return 0

