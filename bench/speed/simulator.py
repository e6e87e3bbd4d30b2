"""make bench's simulator section: the fake robot's CPU at 1x, and the
simulated out-and-back's launch at full speed, beside other commits.

Each side is a workspace (this one, and each of ``--sim-against``, built
by ``make build WS=...``); rounds alternate the sides, so every side meets
the same machine in the same sitting. Per round and side:

- robot: a fresh ``roscore``, ``rosrun rbx1_nav fake_turtlebot.py``
  (free-running at 1x, as a reader leaves it running) and one default
  ``rosrun rbx1_nav odom_out_and_back.py``: the robot's CPU seconds from
  the course's start to its exit.
- launch: ``roslaunch rbx1_nav odom_out_and_back_sim.launch
  sim_speed:=max`` with no master running, as a user types it: wall
  seconds from roslaunch's start to its exit, and CPU seconds (user +
  system of roslaunch and every process it started); the course's speed
  (simulated over wall seconds from "Following tf" to "course done", the
  stamps of its own log lines) and its end pose, from its summary line.

The figures are medians over rounds; ratios compare sides from the same
run. Run by bench/bench.py (``--sections simulator``) or alone:
python3 bench/speed/simulator.py --against /work/ws/old --rounds 3
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
from common import free_port, log  # noqa: E402
from speed.course_cpu import Robot, wait4  # noqa: E402
from speed.courses import sourced  # noqa: E402

STAMPED = re.compile(r'\[INFO\] \[([0-9.]+), ([0-9.]+)\]: (.*)')
END_POSE = re.compile(r'error from the ideal end pose: position ([0-9.]+) mm, '
                      r'heading ([-+0-9.]+) deg')


def robot_round(env):
    """The fake robot's CPU seconds for one default course at 1x."""
    robot = Robot(env)
    try:
        before = robot.cpu().get('fake_turtlebot', 0.0)
        course = subprocess.run(['rosrun', 'rbx1_nav', 'odom_out_and_back.py'], env=robot.env,
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                stdin=subprocess.DEVNULL, universal_newlines=True, timeout=120)
        cpu = robot.cpu().get('fake_turtlebot', 0.0) - before
    finally:
        robot.close()
    return dict(robot_cpu=cpu, completed='Course complete' in course.stdout)


def launch_round(env):
    """One simulated launch at full speed: wall, CPU, course speed, end pose."""
    env = dict(env, ROS_MASTER_URI='http://localhost:%d' % free_port())
    started = time.monotonic()
    proc = subprocess.Popen(['roslaunch', 'rbx1_nav', 'odom_out_and_back_sim.launch',
                             'sim_speed:=max'], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                            universal_newlines=True, start_new_session=True)
    out = proc.stdout.read()
    cpu = wait4(proc)
    wall = time.monotonic() - started
    stamps = {}
    for wall_stamp, sim_stamp, text in STAMPED.findall(out):
        for key in ('Following tf', 'course done'):
            if text.startswith(key):
                stamps[key] = (float(wall_stamp), float(sim_stamp))
    pose = END_POSE.search(out)
    result = dict(wall=wall, cpu=cpu, completed=bool(pose) and proc.returncode == 0)
    if pose and len(stamps) == 2:
        (w0, s0), (w1, s1) = stamps['Following tf'], stamps['course done']
        result.update(speed=(s1 - s0) / (w1 - w0), error_mm=float(pose.group(1)),
                      heading_deg=float(pose.group(2)))
    return result


def run(against=(), rounds=3):
    """The section's result: every round of every side, and the medians."""
    sides = [('this commit', dict(os.environ))] + [
        (os.path.basename(os.path.normpath(ws)), sourced(ws)) for ws in against]
    results = {name: [] for name, _ in sides}
    for i in range(rounds):
        order = sides if i % 2 == 0 else sides[::-1]
        for name, env in order:
            row = dict(robot_round(env), **launch_round(env))
            results[name].append(row)
            log('simulator round %d, %s: robot %.2f CPU s; launch %.2f s wall, %.2f CPU s, '
                'course %.1fx, ends %s mm, %s deg%s' % (
                    i + 1, name, row['robot_cpu'], row['wall'], row['cpu'],
                    row.get('speed', 0.0), row.get('error_mm'), row.get('heading_deg'),
                    '' if row['completed'] else ' (NOT COMPLETED)'))
    medians = {name: {key: statistics.median(r[key] for r in rows if key in r)
                      for key in ('robot_cpu', 'wall', 'cpu', 'speed')}
               for name, rows in results.items()}
    return dict(rounds=rounds, sides=[name for name, _ in sides], medians=medians,
                runs=results, all_completed=all(r['completed'] for rows in results.values()
                                                for r in rows))


def markdown(section):
    """The section's table: medians, and each side's ratio to this commit."""
    med = section['medians']
    ours = med['this commit']
    out = ['## The simulator: fake robot at 1x, simulated launch at full speed', '',
           '%d rounds, sides alternating (bench/speed/simulator.py); medians. Robot: the '
           'fake robot\'s CPU for one default course at 1x. Launch: `roslaunch rbx1_nav '
           'odom_out_and_back_sim.launch sim_speed:=max`, no master running, from its '
           'start to its exit. Course: simulated / wall s of the course itself.' % (
               section['rounds']), '',
           '| side | robot CPU s | launch wall s | launch CPU s | course speed | end pose '
           '(mm, deg) | this commit / side: robot, wall, CPU |',
           '|---|---|---|---|---|---|---|']
    for name in section['sides']:
        m, rows = med[name], section['runs'][name]
        poses = sorted({(r.get('error_mm'), r.get('heading_deg')) for r in rows})
        out.append('| %s | %.2f | %.2f | %.2f | %.1fx | %s | %s |' % (
            name, m['robot_cpu'], m['wall'], m['cpu'], m['speed'],
            ', '.join('%s, %s' % p for p in poses),
            '-' if name == 'this commit' else '%.2f, %.2f, %.2f' % (
                ours['robot_cpu'] / m['robot_cpu'], ours['wall'] / m['wall'],
                ours['cpu'] / m['cpu'])))
    return out + ['']


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--against', nargs='*', default=[], metavar='WORKSPACE')
    parser.add_argument('--rounds', type=int, default=3)
    args = parser.parse_args()
    print('\n'.join(markdown(run(args.against, args.rounds))))


if __name__ == '__main__':
    main()
