#!/usr/bin/env python3
"""pose_ekf's GPS modes on robot_pose_ekf's own Husky bag, without ROS
running: the bag's /encoder, /imu_data and /gps fed to
rbx1_nav.estimation.fusion.GyroOdomFusion as pose_ekf.py feeds them (ROS time is
each message's record time; the filter steps ~freq times a second).

Prints each mode's last pose before robot_pose_ekf's test time beside what
that test expects, and plots the GPS fixes, the odometry and both
estimates in the GPS frame (docs/pose_ekf_husky_gps.png).

Usage: python3 bench/accuracy/pose_ekf_husky.py [-o PNG] [BAG]
"""
import argparse
import math
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, 'src'))
from rbx1_nav.estimation.input_check import RejectedInput  # noqa: E402
from rbx1_nav.estimation.ekf import pose_covariance_3x3, position_covariance_2x2  # noqa: E402
from rbx1_nav.estimation.fusion import GyroOdomFusion  # noqa: E402
from rbx1_nav.transform_utils import quat_to_angle  # noqa: E402

BAG = os.path.join(ROOT, 'test', 'data', 'gps_data.bag')
#: robot_pose_ekf's test (test_robot_pose_ekf_gps.cpp): the last estimate
#: stamped before END is expected at EXPECTED (x, y m, yaw deg).
END = 1368022016.0
EXPECTED = (1.669542, -3.849846, -73.42)
#: pose_ekf's modes on the bag: the node's GPS parameters.
MODES = {
    'robot_pose_ekf (gps_used)': {},
    'gps_frame_rotation': {'gps_frame_rotation': math.radians(30.0)},
}


def read_bag(path=BAG):
    """The bag's sensor messages as ``(received, sensor, stamp, value,
    covariance)``, in recorded order, as pose_ekf.py unpacks them."""
    import rosbag
    messages = []
    with rosbag.Bag(path) as bag:
        for topic, msg, received in bag.read_messages(
                topics=['/encoder', '/imu_data', '/gps']):
            row = (received.to_sec(), msg.header.stamp.to_sec())
            if topic == '/encoder':
                pose = msg.pose.pose
                messages.append(row[:1] + ('odom',) + row[1:] + (
                    (pose.position.x, pose.position.y,
                     quat_to_angle(pose.orientation)),
                    pose_covariance_3x3(msg.pose.covariance)))
            elif topic == '/imu_data':
                messages.append(row[:1] + ('imu',) + row[1:] + (
                    quat_to_angle(msg.orientation),
                    msg.orientation_covariance[8]))
            else:
                position = msg.pose.pose.position
                messages.append(row[:1] + ('gps',) + row[1:] + (
                    (position.x, position.y),
                    position_covariance_2x2(msg.pose.covariance)))
    return messages


def replay(fusion, messages, freq=30.0, skip=0.0, ticks=None):
    """Feed ``messages`` (:func:`read_bag`) from ``skip`` s into the bag on;
    the filter steps at ``ticks`` (ROS times; default every 1/freq s).
    Returns every estimate ``(stamp, (x, y, yaw), cov3)`` made."""
    first = messages[0][0] + skip
    if ticks is None:
        ticks = np.arange(first, messages[-1][0] + 1.0, 1.0 / freq)
    ticks = iter(ticks)
    tick, estimates = next(ticks), []
    fusion.start(first)
    for received, sensor, stamp, value, cov in messages:
        if received < first:
            continue
        while tick is not None and tick <= received:
            fusion.step(tick)
            estimates.extend(fusion.new_estimates)
            tick = next(ticks, None)
        try:
            getattr(fusion, 'add_' + sensor)(received, stamp, value, cov)
        except RejectedInput:
            pass
    return estimates


def last_before(estimates, end=END):
    """The last estimate stamped before ``end``."""
    return [e for e in estimates if e[0] < end][-1]


def plot(messages, results, path):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fixes = np.array([m[3] for m in messages if m[1] == 'gps'])
    odom = [m for m in messages if m[1] == 'odom']
    imu_yaw = next(m[3] for m in messages if m[1] == 'imu')
    # Odometry in the GPS frame as robot_pose_ekf starts it: from the
    # first fix, turned so its first heading is the IMU's.
    x0, y0, yaw0 = odom[0][3]
    turn = imu_yaw - yaw0
    c, s = math.cos(turn), math.sin(turn)
    track = np.array([(fixes[0][0] + c * (x - x0) - s * (y - y0),
                       fixes[0][1] + s * (x - x0) + c * (y - y0))
                      for x, y, _ in (m[3] for m in odom)])
    fig, ax = plt.subplots(figsize=(7, 6))
    ax.plot(fixes[:, 0], fixes[:, 1], '.', color='0.5', label='GPS fixes')
    ax.plot(track[:, 0], track[:, 1], ':', color='tab:green',
            label='wheel odometry (from the first fix, IMU heading)')
    for (name, estimates), color in zip(results.items(),
                                        ('tab:red', 'tab:blue')):
        xy = np.array([e[1][:2] for e in estimates])
        ax.plot(xy[:, 0], xy[:, 1], '-', color=color, label='pose_ekf: ' + name)
    ax.plot(*EXPECTED[:2], 'kx', markersize=10,
            label="robot_pose_ekf's test expects")
    ax.set_aspect('equal')
    ax.set_xlabel('x (m, GPS frame)')
    ax.set_ylabel('y (m, GPS frame)')
    ax.set_title("robot_pose_ekf's Husky bag (gps_data.bag)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=90)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('bag', nargs='?', default=BAG)
    parser.add_argument('-o', '--output', default=os.path.join(
        ROOT, 'docs', 'pose_ekf_husky_gps.png'))
    args = parser.parse_args()
    messages = read_bag(args.bag)
    results = {}
    print('robot_pose_ekf expects: (%.3f, %.3f) m, yaw %.2f deg' % EXPECTED)
    for name, options in MODES.items():
        fusion = GyroOdomFusion(gps_used=True, **options)
        results[name] = replay(fusion, messages)
        _, (x, y, yaw), _ = last_before(results[name])
        rotation = fusion.ekf.rotation
        print('%s: (%.3f, %.3f) m, yaw %.2f deg%s' % (
            name, x, y, math.degrees(yaw), '' if rotation is None else
            '; rotation %.2f deg (sd %.2f)' % (
                math.degrees(rotation[0]), math.degrees(math.sqrt(rotation[1])))))
    plot(messages, results, args.output)
    print('plotted ' + args.output)


if __name__ == '__main__':
    main()
