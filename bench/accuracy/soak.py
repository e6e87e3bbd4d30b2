#!/usr/bin/env python3
"""Soak lockstep simulated time: N courses back to back beside K CPU burners.

Each run is one ``roslaunch`` on a master of its own, at ``sim_speed:=max``
(lockstep), the way a user starts it: the out-and-back course, the same in
precise mode, the square, and a fleet of four robots each driving the
course. A run *completes* when every course logged its summary line,
*aborts* when roslaunch ends without them (a course node exited 1), and
*hangs* when neither happens within ``--limit`` wall seconds (the failure
this tool exists to find: simulated time stopped for good). It also counts
the lines in which sim_clock says whom it waits for (a member slow for over
a second). Not a test: run it on demand, e.g.

    python3 bench/accuracy/soak.py --runs 200 --burners 2

(source the workspace first, as `make bench` does). Prints a table per
course kind: runs, completed, aborted, hangs, slow-member lines, and the
wall seconds per run (median and max).
"""
import argparse
import os
import statistics
import subprocess
import sys
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from common import end_processes, free_port  # noqa: E402

#: (name, launch file, arguments, summary lines expected)
COURSES = (
    ('out_and_back', 'odom_out_and_back_sim.launch', {}, 1),
    ('precise', 'odom_out_and_back_sim.launch', {'precise': 'true'}, 1),
    ('square', 'nav_square.launch', {'sim': 'true'}, 1),
    ('fleet4', 'fleet.launch', {'n': '4', 'course': 'true'}, 4),
)
SUMMARY = 'Course complete in'
SLOW = 'simulated time waits at'


def run_once(launch, args, expected, limit):
    """One roslaunch; returns (outcome, wall seconds, slow-member lines)."""
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI='http://localhost:%d' % port,
               PYTHONUNBUFFERED='1')
    env.pop('ROS_NAMESPACE', None)
    argv = ['roslaunch', '-p', str(port), 'rbx1_nav', launch, 'sim_speed:=max']
    argv += ['%s:=%s' % kv for kv in sorted(args.items())]
    started = time.monotonic()
    proc = subprocess.Popen(argv, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, universal_newlines=True,
                            start_new_session=True)
    counts = {'done': 0, 'slow': 0}

    def read():
        for line in proc.stdout:
            counts['done'] += SUMMARY in line
            counts['slow'] += SLOW in line

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    outcome = 'aborted'
    while True:
        if counts['done'] >= expected:
            outcome = 'completed'
            break
        if not reader.is_alive():
            break
        if time.monotonic() - started > limit:
            outcome = 'hang'
            break
        time.sleep(0.02)
    wall = time.monotonic() - started
    end_processes([proc], 30)
    return outcome, wall, counts['slow']


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--runs', type=int, default=20,
                        help='runs in all, shared round-robin by the course kinds')
    parser.add_argument('--burners', type=int, default=2, help='CPU burners beside')
    parser.add_argument('--limit', type=float, default=120.0,
                        help='wall seconds after which a run counts as hung')
    args = parser.parse_args()
    burners = [subprocess.Popen(['yes'], stdout=subprocess.DEVNULL)
               for _ in range(args.burners)]
    stats = {name: dict(runs=0, completed=0, aborted=0, hang=0, slow=0, walls=[])
             for name, _, _, _ in COURSES}
    try:
        for i in range(args.runs):
            name, launch, launch_args, expected = COURSES[i % len(COURSES)]
            outcome, wall, slow = run_once(launch, launch_args, expected, args.limit)
            row = stats[name]
            row['runs'] += 1
            row[outcome] += 1
            row['slow'] += slow
            row['walls'].append(wall)
            sys.stderr.write('%3d/%d %-12s %-9s %5.1f s wall%s\n' % (
                i + 1, args.runs, name, outcome, wall,
                ', %d slow-member lines' % slow if slow else ''))
    finally:
        for proc in burners:
            proc.kill()
            proc.wait()
    print('| course | runs | completed | aborted | hangs | slow-member lines '
          '| wall s per run (median, max) |')
    print('|---|---|---|---|---|---|---|')
    for name, row in stats.items():
        walls = row['walls'] or [float('nan')]
        print('| %s | %d | %d | %d | %d | %d | %.1f, %.1f |' % (
            name, row['runs'], row['completed'], row['aborted'], row['hang'],
            row['slow'], statistics.median(walls), max(walls)))
    print('%d runs, %d burners: %d hangs, %d aborts' % (
        args.runs, args.burners, sum(r['hang'] for r in stats.values()),
        sum(r['aborted'] for r in stats.values())))


if __name__ == '__main__':
    main()
