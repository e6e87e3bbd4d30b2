#!/usr/bin/env python3
"""How many robots, each driving its course, this machine holds at 1x.

For each fleet size N and mode, runs
``roslaunch rbx1_nav fleet.launch n:=N course:=true`` (mode ``fleet``: one
fake_fleet.py process simulates every robot; mode ``separate``: one
fake_turtlebot.py per robot, ``separate:=true``) on a roscore of its own,
until every robot's odom_out_and_back.py has ended, and reports:

- completed: courses that logged "Course complete" (of N);
- control rate: the median of the courses' mean control-loop rates and
  the fewest ticks any course made in one second of ROS time;
- course error: the worst "error from the ideal end pose" the courses
  logged (measured by their odometry);
- true error: the worst distance and heading between each robot's
  ground_truth after its course and the world origin, where every robot of
  fleet.launch starts;
- CPU seconds (user + system, from /proc) of the simulator process(es), of
  the N course nodes, and their total, over the run;
- holds: every course completed and both errors within the tolerance (the
  single robot's rostest limits, 20 mm and 1.5 deg, by default).

Usage (workspace sourced, /usr/bin first on PATH):
    python3 bench/speed/fleet_scale.py --n 10 20 40 60 80 --modes fleet separate
    python3 bench/speed/fleet_scale.py --n 40 --json      # results as JSON
Each run prints a progress line on stderr; the table (or JSON) goes to
stdout. ``run_fleet(n, mode)`` and ``run_all(...)`` return the same results
as dicts, for other scripts. Results depend on the machine and its load:
compare rows of one run, and read the load averages printed with them.
"""
import argparse
import json
import math
import os
import re
import statistics
import subprocess
import sys
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from common import cpu_seconds, descendants, end_processes, fmt, log  # noqa: E402
from graph import Master  # noqa: E402

MODES = ('fleet', 'separate')
POSITION_LIMIT = 0.020  # m: the single robot's book-mode rostest limits
HEADING_LIMIT = 1.5     # deg
COURSE_LINE = re.compile(
    r'Course complete in (?P<time>[\d.]+) s: final pose relative to start in '
    r'(?P<robot>\S+)/odom: .*error from the ideal end pose: position '
    r'(?P<mm>[\d.]+) mm, heading (?P<deg>[-+\d.]+) deg')
RATE_LINE = re.compile(r'final pose relative to start in (?P<robot>\S+)/odom: .*'
                       r'control loop (?P<hz>[\d.]+) Hz mean, (?P<slowest>\d+) Hz slowest')
# roslaunch's own lines when a course node exits.
COURSE_EXIT = re.compile(
    r'\[(?P<robot>[^\s/\]]+)/odom_out_and_back-\d+\] (?P<how>process has '
    r'finished cleanly|process has died)')


def role(cmdline):
    """Which part of the fleet a process is, from its command line."""
    for script, name in (('fake_fleet.py', 'simulator'),
                         ('fake_turtlebot.py', 'simulator'),
                         ('odom_out_and_back.py', 'courses'),
                         ('sim_clock.py', 'clock')):
        if script in cmdline:
            return name
    return 'launcher'


class CpuMeter(object):
    """CPU seconds of a process tree, sampled, kept for exited processes.

    A process's last sample stands for its total, so one that exits between
    samples loses at most one sampling period of CPU (course nodes exit
    right after their summary line, when they do little).
    """

    def __init__(self, root, period=0.5):
        self.root, self.period = root, period
        self.seen = {}  # pid: [role, first cpu, last cpu]
        self.stopped = threading.Event()
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def sample(self):
        for pid, cmdline in descendants(self.root).items():
            cpu = cpu_seconds(pid)
            if cpu is None:
                continue
            if pid not in self.seen:
                # Processes started after the meter count from zero.
                self.seen[pid] = [role(cmdline), 0.0, cpu]
            self.seen[pid][2] = cpu

    def _run(self):
        while not self.stopped.is_set():
            self.sample()
            self.stopped.wait(self.period)

    def stop(self):
        self.sample()
        self.stopped.set()
        self.thread.join()
        totals = {}
        for name, first, last in self.seen.values():
            totals[name] = totals.get(name, 0.0) + last - first
        return totals


def true_errors(robots, rospy, Odometry, wall_limit=10.0):
    """{robot: (m, deg)} between its ground_truth now and the origin."""
    from rbx1_nav.transform_utils import quat_to_angle
    errors = {}
    for robot in robots:
        try:
            msg = rospy.wait_for_message('/%s/ground_truth' % robot, Odometry,
                                         timeout=wall_limit)
        except rospy.ROSException:
            continue
        p = msg.pose.pose
        errors[robot] = (math.hypot(p.position.x, p.position.y),
                         abs(math.degrees(quat_to_angle(p.orientation))))
    return errors


class Bench(Master):
    """A master of this process's own for every run of the fleet."""

    def run_fleet(self, n, mode='fleet', sim_speed=0.0, precise=False,
                  position_limit=POSITION_LIMIT, heading_limit=HEADING_LIMIT,
                  wall_limit=None, physics=False):
        """One run of N robots; returns its results as a dict."""
        if mode not in MODES:
            raise ValueError('mode must be one of %s, got %r' % (MODES, mode))
        rospy = self.rospy
        if sim_speed > 0:
            rospy.set_param('/use_sim_time', True)
        elif rospy.has_param('/use_sim_time'):
            rospy.delete_param('/use_sim_time')
        robots = ['robot%d' % k for k in range(1, n + 1)]
        # Start-up (every process at once), the course (about 35 s of ROS
        # time), margin.
        wall_limit = wall_limit or 30.0 + 1.5 * n + 60.0 / max(sim_speed, 1.0)
        args = ['roslaunch', '-p', str(self.port), 'rbx1_nav', 'fleet.launch',
                'n:=%d' % n, 'course:=true', 'separate:=%s' % str(mode == 'separate').lower(),
                'precise:=%s' % str(precise).lower(), 'sim_speed:=%g' % sim_speed,
                'physics:=%s' % str(physics).lower(),
                # The robots stay up after the courses: their ground truth
                # is read below.
                'end:=false']
        load_before = os.getloadavg()[0]
        start = time.monotonic()
        launch = subprocess.Popen(args, env=self.env, stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, universal_newlines=True,
                                  start_new_session=True)
        meter = CpuMeter(launch.pid)
        done, lines, exits, rates = {}, [], {}, {}

        def read():
            for line in launch.stdout:
                lines.append(line.rstrip())
                match = COURSE_LINE.search(line)
                if match:
                    done[match.group('robot')] = (float(match.group('mm')),
                                                  abs(float(match.group('deg'))),
                                                  float(match.group('time')))
                match = RATE_LINE.search(line)
                if match:
                    rates[match.group('robot')] = (float(match.group('hz')),
                                                   int(match.group('slowest')))
                match = COURSE_EXIT.search(line)
                if match:
                    exits[match.group('robot')] = match.group('how')

        reader = threading.Thread(target=read, daemon=True)
        reader.start()
        while (len(exits) < n and launch.poll() is None
               and time.monotonic() - start < wall_limit):
            time.sleep(0.2)
        wall = time.monotonic() - start
        truth = true_errors([r for r in robots if r in done], rospy, self.Odometry)
        cpu = meter.stop()
        load_after = os.getloadavg()[0]
        end_processes([launch], 30)
        reader.join(5.0)
        failed = sorted(set(robots) - set(done), key=lambda r: int(r[5:]))
        worst = lambda values, i: max((v[i] for v in values), default=float('nan'))  # noqa: E731
        result = dict(
            n=n, mode=mode, sim_speed=sim_speed, precise=precise,
            completed=len(done), failed=failed,
            course_mm=worst(done.values(), 0), course_deg=worst(done.values(), 1),
            true_mm=1000.0 * worst(truth.values(), 0), true_deg=worst(truth.values(), 1),
            truth_read=len(truth),
            rate_median=(statistics.median(r[0] for r in rates.values())
                         if rates else float('nan')),
            rate_min=min((r[1] for r in rates.values()), default=float('nan')),
            cpu_simulator=cpu.get('simulator', 0.0), cpu_courses=cpu.get('courses', 0.0),
            cpu_clock=cpu.get('clock', 0.0), cpu_launcher=cpu.get('launcher', 0.0),
            wall=wall, timed_out=len(exits) < n,
            load_before=load_before, load_after=load_after, cpus=os.cpu_count(),
            position_limit_mm=1000.0 * position_limit, heading_limit_deg=heading_limit)
        result['cpu_total'] = sum(cpu.values())
        result['holds'] = (len(done) == n and len(truth) == n
                           and result['course_mm'] <= 1000.0 * position_limit
                           and result['true_mm'] <= 1000.0 * position_limit
                           and result['course_deg'] <= heading_limit
                           and result['true_deg'] <= heading_limit)
        if failed:
            result['failure_lines'] = [l for l in lines if 'ERROR' in l or 'died' in l][:10]
        return result


def run_all(sizes, modes=MODES, sim_speed=0.0, precise=False,
            position_limit=POSITION_LIMIT, heading_limit=HEADING_LIMIT, log=None,
            physics=False):
    """Every (N, mode) in turn on one roscore; a list of result dicts.

    Larger sizes of a mode are skipped once two sizes in a row did not hold.
    """
    bench = Bench()
    results = []
    try:
        for mode in modes:
            misses = 0
            for n in sizes:
                if misses >= 2:
                    break
                result = bench.run_fleet(n, mode, sim_speed, precise,
                                         position_limit, heading_limit,
                                         physics=physics)
                results.append(result)
                misses = 0 if result['holds'] else misses + 1
                if log:
                    log(result)
    finally:
        bench.close()
    return results


def largest_holding(results, mode):
    """The largest N of ``mode`` that held, or None."""
    held = [r['n'] for r in results if r['mode'] == mode and r['holds']]
    return max(held) if held else None


def table(results):
    """A markdown table of the results."""
    rows = ['| N | mode | completed | worst course error (mm / deg) | worst true '
            'error (mm / deg) | CPU s: simulator / courses / total | wall s | '
            'load before / after | holds |',
            '|---|---|---|---|---|---|---|---|---|']
    for r in results:
        rows.append('| %d | %s | %d/%d | %.1f / %.2f | %.1f / %.2f | %.1f / %.1f / %.1f '
                    '| %.0f | %.1f / %.1f | %s |' % (
                        r['n'], r['mode'], r['completed'], r['n'], r['course_mm'],
                        r['course_deg'], r['true_mm'], r['true_deg'], r['cpu_simulator'],
                        r['cpu_courses'], r['cpu_total'], r['wall'], r['load_before'],
                        r['load_after'], 'yes' if r['holds'] else 'no'))
    return '\n'.join(rows)


# -- make bench's scale section ------------------------------------------

#: The target shown beside each row (the GUIDE's).
TARGET = 'every course within 20 mm, 1.5 deg'


def section(counts):
    """make bench's scale section: :func:`run_all` over ``counts`` at 1x
    (no simulated time), one fake_fleet and separate fake_turtlebot
    processes."""
    rows = run_all(counts, log=lambda r: log(
        'scale %d robots (%s): %d/%d completed, worst %.1f mm, %.2f deg, %.0f CPU s'
        % (r['n'], r['mode'], r['completed'], r['n'], r['true_mm'], r['true_deg'],
           r['cpu_total'])))
    for row in rows:
        row['target'] = TARGET
    return rows


def section_markdown(rows):
    """The scale section's table, as lines."""
    out = ['## Scale (1x, the default course on every robot)', '',
           '| robots | simulators | completed | worst true error | control rate: '
           'median / slowest second | total CPU s | holds | target |',
           '|---|---|---|---|---|---|---|---|']
    for r in rows:
        out.append('| %d | %s | %d/%d | %s mm, %s deg | %s Hz / %s ticks | %s | %s | %s |' % (
            r['n'], 'one fake_fleet' if r['mode'] == 'fleet' else 'separate',
            r['completed'], r['n'], fmt(r['true_mm']), fmt(r['true_deg'], '%.2f'),
            fmt(r.get('rate_median')), fmt(r.get('rate_min'), '%.0f'),
            fmt(r['cpu_total'], '%.0f'), 'yes' if r['holds'] else 'no', r['target']))
    out.append('')
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--n', type=int, nargs='+', default=[10, 20, 40, 60, 80],
                        help='fleet sizes, in increasing order')
    parser.add_argument('--modes', nargs='+', choices=MODES, default=list(MODES))
    parser.add_argument('--sim-speed', type=float, default=0.0,
                        help='0: real time (1x without a clock); S: /clock at S x')
    parser.add_argument('--precise', action='store_true', help="the courses' precise mode")
    parser.add_argument('--position-limit', type=float, default=POSITION_LIMIT, help='m')
    parser.add_argument('--heading-limit', type=float, default=HEADING_LIMIT, help='deg')
    parser.add_argument('--json', action='store_true', help='print the results as JSON')
    args = parser.parse_args(argv)

    def log(r):
        print('%s n=%d: %d/%d courses, worst %.1f mm %.2f deg (true %.1f mm %.2f deg), '
              'CPU %.0f s, %s' % (r['mode'], r['n'], r['completed'], r['n'], r['course_mm'],
                                 r['course_deg'], r['true_mm'], r['true_deg'],
                                 r['cpu_total'], 'holds' if r['holds'] else 'does not hold'),
              file=sys.stderr)

    results = run_all(sorted(args.n), args.modes, args.sim_speed, args.precise,
                      args.position_limit, args.heading_limit, log)
    if args.json:
        print(json.dumps(results, indent=1))
        return
    print(table(results))
    for mode in args.modes:
        print('%s: largest N that held (%g mm, %g deg): %s' % (
            mode, 1000.0 * args.position_limit, args.heading_limit,
            largest_holding(results, mode)))


if __name__ == '__main__':
    main()
