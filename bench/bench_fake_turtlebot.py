#!/usr/bin/env python3
"""Benchmark nodes/fake_turtlebot.py: CPU cost and the sim speed it sustains.

Starts its own roscore on a free port, then for each sim speed runs
sim_clock.py and fake_turtlebot.py (driving a constant arc) for a fixed span
of simulated time, and prints a markdown table:

- achieved speed: simulated seconds per wall second the clock reached;
- odom rate: odometry messages per simulated second (the node's ~rate is 50);
- max gap: largest jump between consecutive odom stamps (1/rate when the
  node keeps up; larger when it had to skip ahead);
- CPU s / sim s: CPU seconds (user + system) each process used per simulated
  second.

Usage: python3 bench/bench_fake_turtlebot.py [--speeds 1 5 10 20 40] [--sim-seconds 10]
Needs the workspace sourced (source ~/.cache/rbx1_nav/ws/devel/setup.bash).
Results depend on the machine and its load; compare rows of one run.
"""
import argparse
import os
import signal
import socket
import subprocess
import sys
import time

RATE = 50.0


def free_port():
    with socket.socket() as s:
        s.bind(('localhost', 0))
        return s.getsockname()[1]


def cpu_seconds(pid):
    """User + system CPU seconds of a process, from /proc."""
    with open('/proc/%d/stat' % pid) as f:
        fields = f.read().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')


def start(cmd, env):
    return subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, start_new_session=True)


def stop(proc):
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGINT)
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def run_speed(rospy, msgs, speed, sim_seconds, start_time, env):
    """One row: start clock and robot, drive, measure, stop them."""
    clock = start(['rosrun', 'rbx1_nav', 'sim_clock.py', '_speed:=%g' % speed,
                   '_start_time:=%g' % start_time], env)
    robot = start(['rosrun', 'rbx1_nav', 'fake_turtlebot.py', '_cmd_timeout:=1000000.0',
                   '__name:=fake_turtlebot'], env)
    stamps = []
    sub = rospy.Subscriber('odom', msgs.Odometry,
                           lambda m: stamps.append((m.header.seq, m.header.stamp.to_sec())),
                           queue_size=100000)
    pub = rospy.Publisher('cmd_vel', msgs.Twist, queue_size=1)
    deadline = time.monotonic() + 60
    while (pub.get_num_connections() == 0 or len(stamps) < 10) and time.monotonic() < deadline:
        time.sleep(0.05)
    twist = msgs.Twist()
    twist.linear.x, twist.angular.z = 0.2, 0.3
    pub.publish(twist)
    time.sleep(0.2)
    t0_sim, t0_wall = rospy.Time.now().to_sec(), time.monotonic()
    cpu0 = cpu_seconds(robot.pid), cpu_seconds(clock.pid)  # rosrun execs the node
    n0 = len(stamps)
    while rospy.Time.now().to_sec() - t0_sim < sim_seconds and time.monotonic() < t0_wall + 600:
        time.sleep(0.05)
    t1_sim, t1_wall = rospy.Time.now().to_sec(), time.monotonic()
    cpu1 = cpu_seconds(robot.pid), cpu_seconds(clock.pid)  # rosrun execs the node
    window = stamps[n0:]
    sub.unregister()
    pub.unregister()
    stop(robot)
    stop(clock)
    sim = t1_sim - t0_sim
    (seq0, s0), (seq1, s1) = window[0], window[-1]
    gaps = [b[1] - a[1] for a, b in zip(window, window[1:])]
    return dict(speed=speed, achieved=sim / (t1_wall - t0_wall),
                rate=(seq1 - seq0) / (s1 - s0), max_gap=max(gaps),
                robot_cpu=(cpu1[0] - cpu0[0]) / sim, clock_cpu=(cpu1[1] - cpu0[1]) / sim,
                end=t1_sim)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--speeds', type=float, nargs='+', default=[1, 5, 10, 20, 40])
    parser.add_argument('--sim-seconds', type=float, default=10.0)
    args = parser.parse_args()

    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI='http://localhost:%d' % port)
    os.environ.update(env)
    core = start(['roscore', '-p', str(port)], env)
    try:
        import rospy
        from geometry_msgs.msg import Twist
        from nav_msgs.msg import Odometry
        msgs = type('msgs', (), dict(Twist=Twist, Odometry=Odometry))
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            try:
                rospy.get_master().getPid()
                break
            except (ConnectionError, OSError):
                time.sleep(0.2)
        rospy.set_param('/use_sim_time', True)
        rospy.init_node('bench_fake_turtlebot', disable_signals=True)
        rows, start_time = [], 0.0
        for speed in args.speeds:
            row = run_speed(rospy, msgs, speed, args.sim_seconds, start_time, env)
            start_time = row['end'] + 1.0
            rows.append(row)
            print('speed %gx done' % speed, file=sys.stderr)
    finally:
        stop(core)

    print('| sim speed | achieved | odom rate (Hz, sim) | max odom gap (s) '
          '| fake_turtlebot CPU s / sim s | sim_clock CPU s / sim s |')
    print('|---|---|---|---|---|---|')
    for r in rows:
        print('| %gx | %.1fx | %.1f | %.3f | %.3f | %.3f |' % (
            r['speed'], r['achieved'], r['rate'], r['max_gap'], r['robot_cpu'], r['clock_cpu']))
    keeping_up = [r['achieved'] for r in rows
                  if r['rate'] >= 0.98 * RATE and r['max_gap'] <= 2.0 / RATE + 1e-6]
    print('\nHighest achieved sim speed at which fake_turtlebot still published at '
          '%g Hz with no skipped steps: %s (load average at end: %.1f, %d CPUs)' % (
              RATE, '%.1fx' % max(keeping_up) if keeping_up else 'none',
              os.getloadavg()[0], os.cpu_count()))

if __name__ == '__main__':
    main()
