#!/usr/bin/env python3
"""plot_course.py - plot an out-and-back run recorded in a bag.

    rosrun rbx1_nav plot_course.py course.bag [-o course.png]

Draws the odometry path (nav_msgs/Odometry on odom) and, when the bag has
it, the simulator's true path (ground_truth), with start and end poses and
the end-vs-start error in the title. A bag from a real robot, with odom
only, works too. Record one with
``roslaunch rbx1_nav odom_out_and_back_sim.launch record:=true``.
No ROS master is needed.
"""
import argparse
import os
import sys

import rosbag

from rbx1_nav.course_plot import Track, describe_error, plot_course
from rbx1_nav.transform_utils import quat_to_angle


def read_tracks(bag_path, topics):
    """One Track per (name, topic) pair, from the Odometry messages in a bag."""
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


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('bag', help='bag file with nav_msgs/Odometry topics')
    parser.add_argument('-o', '--output',
                        help='PNG to write (default: the bag name with .png)')
    parser.add_argument('--odom-topic', default='odom')
    parser.add_argument('--truth-topic', default='ground_truth',
                        help='true pose topic; skipped if not in the bag')
    args = parser.parse_args(argv)
    output = args.output or os.path.splitext(args.bag)[0] + '.png'
    try:
        odom, truth = read_tracks(args.bag, [('odom', args.odom_topic),
                                             ('ground truth', args.truth_topic)])
    except (IOError, OSError, rosbag.ROSBagException) as err:
        print('plot_course: cannot read %s: %s' % (args.bag, err), file=sys.stderr)
        return 1
    if not len(odom):
        print('plot_course: no nav_msgs/Odometry on %s in %s' % (
            args.odom_topic, args.bag), file=sys.stderr)
        return 1
    plot_course([odom, truth], output, title=os.path.basename(args.bag))
    print('plot_course: wrote %s; end vs start: %s' % (output, '; '.join(
        describe_error(t) for t in (odom, truth) if len(t))))
    return 0


if __name__ == '__main__':
    sys.exit(main())
