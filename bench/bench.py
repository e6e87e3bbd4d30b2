#!/usr/bin/env python3
"""make bench: accuracy, speed, CPU and scale of the courses, in one run.

Every figure comes from the same run on the same machine, so ratios between
rows mean something; absolute times depend on the machine and its load.
Each course runs the way a user runs it: a fresh master, the fake robot
from ``fake_turtlebot.launch`` (or ``fake_turtlebot_ekf.launch``), then
``rosrun rbx1_nav odom_out_and_back.py``; the final error is read from the
simulator's ``ground_truth`` after the course (the robot starts at the
origin, and the out-and-back course ends where it began).

Sections (``--sections``, all but population by default):

- accuracy: ``--runs`` runs each of {default, precise} x {ideal,
  realistic, realistic + pose_ekf}, lockstep at full speed (pose_ekf, no
  lockstep member, at 5x); realistic runs use seeds 1..runs. Median and max final error.
- speed: the default course at 1x, 10x and max, lockstep and free-running
  (free-running "max" is the speed lockstep reached); course wall time,
  speed-up, final error.
  Then the CPU seconds per simulated second of every node, the default
  course under lockstep at full speed, ``--speed-rounds`` times; with
  ``--speed-against WORKSPACE`` (another commit's, built by ``make build
  WS=...``) that workspace's course after each of ours, side by side.
- cpu: our out-and-back beside the book's own script (bench/book/), one
  default course each on a fresh master and ``rosrun rbx1_nav
  fake_turtlebot.py`` at 1x, free-running as on a real robot, ``--cpu-rounds``
  rounds alternating: CPU seconds of each course process, the robot, the
  master and rosout; the median ratio ours / book's; the rbx1_nav modules
  our node has loaded at exit (bench/course_cpu.py).
- scale: N robots at 1x, separate processes and one fake_fleet
  (bench/fleet_scale.py).
- physics: the kinematic and the physics robot (MuJoCo) side by side: each
  model stepped alone without ROS (50 Hz, a command each step), each robot
  alone under lockstep at full speed (``idle_speed:=1000000``: unpaced;
  simulated seconds per wall second, read from /clock), the default course at full speed on each, and how
  many physics robots one fake_fleet keeps at 1x (``--robots``).

- population (only when named): docs/calibration.md's procedure on
  ``--population`` robots drawn from ``--seed`` (bench/population.py;
  its own tables, bench/results/population_*.md).

Writes bench/results/latest.md, latest.json and latest.png, and prints the
table. Usage: make bench [BENCH_ARGS="--sections speed --runs 3"]
"""
import argparse
import json
import math
import os
import re
import signal
import statistics
import subprocess
import sys
import time

import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from fleet_scale import cpu_seconds, descendants, free_port, ground_truth  # noqa: E402
import course_cpu  # noqa: E402
import population  # noqa: E402
RESULTS = os.path.join(HERE, 'results')
SUMMARY = re.compile(r'Course complete in ([\d.]+) s')
#: Clock speed (x real time) for courses that follow pose_ekf, which is no
#: lockstep member.
POSE_EKF_SPEED = '5'
#: (m, deg) a course on a physics robot of a fleet must end within to hold
#: 1x: about twice the error of one uncalibrated physics robot on carpet.
PHYSICS_LIMITS = (0.05, 5.0)
#: Targets shown beside each row (the GUIDE's).
TARGETS = {
    'default': 'within 20 mm, 2.5 deg (ideal)',
    'precise': 'within 3 mm, 0.3 deg (ideal)',
    'speed': 'same end pose at every speed (0.1 mm, 0.01 deg)',
    'scale': 'every course within 20 mm, 1.5 deg',
}


def processes(root):
    """{pid: node name} of ``root`` and its descendants (roslaunch puts
    each node in a session of its own, so process groups do not do)."""
    found, family = {}, descendants(root)
    try:
        with open('/proc/%d/cmdline' % root, 'rb') as f:
            family[root] = f.read().replace(b'\0', b' ').decode(errors='replace')
    except OSError:
        pass
    for pid, cmdline in family.items():
        argv = cmdline.split()
        names = [a.split(':=', 1)[1] for a in argv if a.startswith('__name:=')]
        scripts = [os.path.basename(a)[:-3] for a in argv[:3] if a.endswith('.py')]
        if names:
            found[pid] = names[0]
        elif any(a.endswith('rosmaster') for a in argv):
            found[pid] = 'rosmaster'
        elif scripts:
            found[pid] = scripts[0]
    return found


class Graph(object):
    """A master, a launch file and the processes they start (one run)."""

    def __init__(self, launch, args, env=None):
        self.env = dict(env or os.environ, ROS_MASTER_URI='http://localhost:%d' % free_port())
        self.env.pop('ROS_NAMESPACE', None)
        self.env['PYTHONUNBUFFERED'] = '1'  # lines arrive (and are timed) as logged
        port = self.env['ROS_MASTER_URI'].rsplit(':', 1)[1]
        self.launch = subprocess.Popen(
            ['roslaunch', '-p', port, 'rbx1_nav', launch]
            + ['%s:=%s' % kv for kv in sorted(args.items())],
            env=self.env, stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT,
            start_new_session=True)
        self.groups = [self.launch.pid]

    def run(self, script, params, wall_limit):
        """Run a course node to its end; return its lines and timings."""
        cmd = ['rosrun', 'rbx1_nav', script] + [
            '_%s:=%s' % kv for kv in sorted(params.items())]
        proc = subprocess.Popen(cmd, env=self.env, stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT, universal_newlines=True,
                                start_new_session=True)
        self.groups.append(proc.pid)
        lines, started, ended, cpu_start = [], None, None, None
        deadline = time.monotonic() + wall_limit
        for line in proc.stdout:
            lines.append(line.rstrip())
            if started is None and 'Following tf' in line:
                started, cpu_start = time.monotonic(), self.cpu()
            if SUMMARY.search(line):
                ended, cpu_end = time.monotonic(), self.cpu()
            if time.monotonic() > deadline:
                proc.kill()
                break
        proc.wait()
        result = dict(status=proc.returncode, output=lines[-5:])
        match = next((SUMMARY.search(l) for l in lines if SUMMARY.search(l)), None)
        if match and started is not None:
            result.update(sim_s=float(match.group(1)), wall_s=ended - started,
                          cpu={name: cpu_end.get(name, 0.0) - cpu_start.get(name, 0.0)
                               for name in cpu_end})
        return result

    def cpu(self):
        """{node name: CPU seconds so far} over the run's processes."""
        totals = {}
        for group in self.groups:
            for pid, name in processes(group).items():
                totals[name] = totals.get(name, 0.0) + (cpu_seconds(pid) or 0.0)
        return totals

    def truth(self, topic='ground_truth'):
        """(x, y, yaw) of the simulator's next ground_truth message."""
        return ground_truth(self.env, topic)

    def close(self):
        for group in reversed(self.groups):
            try:
                os.killpg(group, signal.SIGINT)
            except ProcessLookupError:
                pass
        try:
            self.launch.wait(15)
        except subprocess.TimeoutExpired:
            os.killpg(self.launch.pid, signal.SIGKILL)
            self.launch.wait()


def course(setup='ideal', mode='default', speed='max', lockstep=True, seed=None,
           physics=False, env=None):
    """One out-and-back course; a result dict (errors on ground truth).
    ``env``: the environment of another workspace (:func:`sourced`)."""
    launch = 'fake_turtlebot_ekf.launch' if setup == 'pose_ekf' else 'fake_turtlebot.launch'
    if setup == 'pose_ekf' and speed == 'max':
        # pose_ekf is no lockstep member: at full speed it falls behind the
        # clock and the course aborts on its stale tf (as in the rostests).
        speed = POSE_EKF_SPEED
    args = dict(sim_speed=speed, model='false')
    if physics:
        args['physics'] = 'true'
    if setup != 'pose_ekf':
        args.update(lockstep=lockstep, realistic=setup == 'realistic')
    if seed is not None and setup != 'ideal':
        args['seed'] = seed
    graph = Graph(launch, args, env)
    try:
        # roslaunch sets /use_sim_time just after its master is up: a course
        # started before that runs on the wall clock against the simulator's
        # stamps and never ends. /clock flowing means the parameter is set.
        clock(graph)
        params = {'precise': mode == 'precise', 'tf_wait': 30.0}
        if not lockstep:  # a node behind the clock must not abort
            params['tf_timeout'] = 5.0
        result = graph.run('odom_out_and_back.py', params, wall_limit=600)
        if result['status'] == 0:
            x, y, yaw = graph.truth()
            result.update(error_mm=1000.0 * math.hypot(x, y),
                          heading_deg=math.degrees(yaw))
    finally:
        graph.close()
    result.update(setup=setup, mode=mode, speed=speed, lockstep=lockstep, seed=seed)
    return result


def clock(graph, wall_limit=60.0):
    """The simulated seconds of the next /clock message (waiting for the
    master and the clock to come up)."""
    deadline = time.monotonic() + wall_limit
    while True:
        out = subprocess.run(['rostopic', 'echo', '-n', '1', '/clock/clock'],
                             env=graph.env, stdout=subprocess.PIPE,
                             stderr=subprocess.DEVNULL, universal_newlines=True,
                             timeout=wall_limit).stdout
        stamp = yaml.safe_load(out.split('---')[0])
        if stamp:
            return stamp['secs'] + 1e-9 * stamp['nsecs']
        if time.monotonic() > deadline:
            raise RuntimeError('no /clock within %.0f s' % wall_limit)
        time.sleep(0.5)


def alone(physics, seconds=10.0):
    """Simulated seconds per wall second of the robot alone under lockstep
    at full speed (no course: only the simulator asks for steps; sim_clock's
    idle pacing off)."""
    graph = Graph('fake_turtlebot.launch', dict(sim_speed='max', model='false',
                                               idle_speed='1000000',
                                               physics=str(physics).lower()))
    try:
        clock(graph)  # up and stepping
        start, wall = clock(graph), time.monotonic()
        time.sleep(seconds)
        return (clock(graph) - start) / (time.monotonic() - wall)
    finally:
        graph.close()


def model_only(physics, seconds=60.0, rate=50.0):
    """Simulated seconds per wall second of the model alone, no ROS: one
    robot stepped at ``rate`` Hz with a command every step."""
    sys.path.insert(0, os.path.join(os.path.dirname(HERE), 'src'))
    from rbx1_nav.sim.diff_drive import DiffDriveFleet
    from rbx1_nav.sim.physics import PhysicsFleet
    fleet = PhysicsFleet(1) if physics else DiffDriveFleet(1)
    now = 0.0
    fleet.step(now)
    start = time.perf_counter()
    for _ in range(int(seconds * rate)):
        fleet.command(0, 0.15, 0.3, now)
        now += 1.0 / rate
        fleet.step(now)
    return seconds / (time.perf_counter() - start)


def physics(counts):
    """The kinematic and the physics robot side by side (see the module
    docstring), and the physics fleet at 1x."""
    rows = []
    for robot in (False, True):
        name = 'physics' if robot else 'kinematic'
        model = model_only(robot)
        log('physics: the %s model alone (no ROS): %.0fx' % (name, model))
        speedup = alone(robot)
        log('physics: the %s robot alone at max: %.0fx' % (name, speedup))
        result = course(physics=robot)
        log('physics: course on the %s robot at max: %s' % (name, describe(result)))
        rows.append(dict(robot=name, model=model, alone=speedup,
                         completed=result['status'] == 0,
                         course_speedup=(result['sim_s'] / result['wall_s']
                                         if result.get('wall_s') else None),
                         error_mm=result.get('error_mm'),
                         heading_deg=result.get('heading_deg')))
    import fleet_scale
    fleet = fleet_scale.run_all(counts, modes=('fleet',), physics=True,
                                position_limit=PHYSICS_LIMITS[0],
                                heading_limit=PHYSICS_LIMITS[1], log=lambda r: log(
        'physics fleet %d robots: %d/%d completed, worst %.1f mm, %.2f deg, %.0f CPU s'
        % (r['n'], r['completed'], r['n'], r['true_mm'], r['true_deg'], r['cpu_total'])))
    return dict(robots=rows, fleet=fleet,
                fleet_holds=fleet_scale.largest_holding(fleet, 'fleet'))


def log(text):
    sys.stderr.write(text + '\n')
    sys.stderr.flush()


def describe(result):
    if 'error_mm' not in result:
        return 'FAILED (exit %s): %s' % (result['status'], ' | '.join(result['output']))
    return '%.1f mm, %+.2f deg, %.1f s sim in %.1f s wall' % (
        result['error_mm'], result['heading_deg'], result['sim_s'], result['wall_s'])


def accuracy(runs):
    rows = []
    for mode in ('default', 'precise'):
        for setup in ('ideal', 'realistic', 'pose_ekf'):
            results = []
            for i in range(runs):
                result = course(setup, mode, seed=i + 1)
                log('accuracy %s %s run %d: %s' % (mode, setup, i + 1, describe(result)))
                results.append(result)
            ok = [r for r in results if 'error_mm' in r]
            pos = [r['error_mm'] for r in ok]
            head = [abs(r['heading_deg']) for r in ok]
            rows.append(dict(
                mode=mode, setup=setup, runs=runs, completed=len(ok),
                median_mm=statistics.median(pos) if ok else None,
                max_mm=max(pos) if ok else None,
                median_deg=statistics.median(head) if ok else None,
                max_deg=max(head) if ok else None,
                target=TARGETS[mode] if setup == 'ideal' else 'reported'))
    return rows


def speed():
    rows = []
    for lockstep in (True, False):
        for speed in ('1', '10', 'max'):
            if speed == 'max' and not lockstep:
                # Free-running at the speed lockstep reached at max.
                reached = next(r for r in rows if r['speed'] == 'max')
                speed = '%.0f' % max(1.0, reached.get('speedup') or 1.0)
            result = course('ideal', 'default', speed, lockstep)
            log('speed %s %sx: %s' % ('lockstep' if lockstep else 'free',
                                       speed, describe(result)))
            row = dict(lockstep=lockstep, speed=speed, completed=result['status'] == 0,
                       error_mm=result.get('error_mm'),
                       heading_deg=result.get('heading_deg'),
                       sim_s=result.get('sim_s'), wall_s=result.get('wall_s'),
                       target=TARGETS['speed'] if lockstep else 'reported')
            if row['wall_s']:
                row['speedup'] = row['sim_s'] / row['wall_s']
            rows.append(row)
    return rows


def sourced(workspace):
    """The environment ``source WORKSPACE/devel/setup.bash`` gives."""
    out = subprocess.run(['bash', '-c', 'source "$0"/devel/setup.bash && env -0', workspace],
                         stdout=subprocess.PIPE, check=True).stdout
    return dict(line.split('=', 1) for line in out.decode().split('\0') if '=' in line)


def cpu_per_sim_s(against=None, rounds=2):
    """CPU seconds per simulated second of each node for the default course
    under lockstep at full speed (from the course's first tick to its
    summary line), ``rounds`` times; with ``against`` (another commit's
    workspace) that workspace's course after each of ours, on the same
    machine in the same sitting."""
    sides = [('this commit', None)]
    if against:
        sides.append((os.path.basename(os.path.normpath(against)), sourced(against)))
    rows = []
    for k in range(rounds):
        for name, env in sides:
            result = course('ideal', 'default', 'max', True, env=env)
            log('cpu per simulated second, round %d, %s: %s' % (k + 1, name, describe(result)))
            if result['status'] != 0 or 'cpu' not in result:
                raise RuntimeError('the course on %s failed: %s' % (name, result['output']))
            per = {n: c / result['sim_s'] for n, c in result['cpu'].items()}
            rows.append(dict(side=name, round=k + 1, sim_s=result['sim_s'],
                             total=sum(per.values()), nodes=per))
    return rows


def scale(counts):
    """bench/fleet_scale.py's runs: N robots at 1x (no simulated time), one
    fake_fleet and separate fake_turtlebot processes."""
    import fleet_scale
    rows = fleet_scale.run_all(counts, log=lambda r: log(
        'scale %d robots (%s): %d/%d completed, worst %.1f mm, %.2f deg, %.0f CPU s'
        % (r['n'], r['mode'], r['completed'], r['n'], r['true_mm'], r['true_deg'],
           r['cpu_total'])))
    for row in rows:
        row['target'] = TARGETS['scale']
    return rows


def fmt(value, spec='%.1f'):
    return '-' if value is None else spec % value


def markdown(results):
    measured = results.get('measured', {})
    out = ['# rbx1_nav bench', '',
           'Machine: %d cores, load average %.1f at the end; %s. Measured: %s. '
           'Compare rows within a section, not machines.' % (
               os.cpu_count(), os.getloadavg()[0], time.strftime('%Y-%m-%d %H:%M'),
               ', '.join('%s %s' % kv for kv in sorted(measured.items())) or 'now'), '']
    if 'accuracy' in results:
        out += ['## Accuracy (lockstep at full speed, pose_ekf rows at %sx; final error '
                'on ground truth)' % POSE_EKF_SPEED, '',
                '| course | robot | completed | median | max | target |',
                '|---|---|---|---|---|---|']
        for r in results['accuracy']:
            out.append('| %s | %s | %d/%d | %s mm, %s deg | %s mm, %s deg | %s |' % (
                r['mode'], r['setup'], r['completed'], r['runs'], fmt(r['median_mm']),
                fmt(r['median_deg'], '%.2f'), fmt(r['max_mm']), fmt(r['max_deg'], '%.2f'),
                r['target']))
        out.append('')
    if 'speed' in results:
        out += ['## Speed (default course, ideal robot)', '',
                '| time | asked | course wall time | speed-up | final error | target |',
                '|---|---|---|---|---|---|']
        for r in results['speed']:
            out.append('| %s | %s | %s s | %s x | %s mm, %s deg | %s |' % (
                'lockstep' if r['lockstep'] else 'free-running',
                r['speed'] if r['speed'] == 'max' else r['speed'] + 'x',
                fmt(r['wall_s']), fmt(r.get('speedup')), fmt(r['error_mm'], '%.2f'),
                fmt(r['heading_deg'], '%+.3f'), r['target']))
        out.append('')
    if 'cpu_per_sim_s' in results:
        rows = results['cpu_per_sim_s']
        sides = list(dict.fromkeys(r['side'] for r in rows))
        nodes = sorted({n for r in rows for n in r['nodes']},
                       key=lambda n: -max(r['nodes'].get(n, 0.0) for r in rows))
        out += ['## CPU seconds per simulated second (default course, lockstep at full '
                'speed; median of %d rounds, alternating)' % max(r['round'] for r in rows), '',
                '| node | %s |' % ' | '.join(sides), '|---|%s' % ('---|' * len(sides))]

        def median(side, key):
            return statistics.median(key(r) for r in rows if r['side'] == side)
        for n in nodes:
            out.append('| %s | %s |' % (n, ' | '.join(
                '%.3f' % median(side, lambda r: r['nodes'].get(n, 0.0)) for side in sides)))
        out.append('| **all** | %s |' % ' | '.join(
            '**%.3f**' % median(side, lambda r: r['total']) for side in sides))
        if len(sides) == 2:
            out += ['', 'Ratio %s / %s: %.2f.' % (sides[0], sides[1], median(
                sides[0], lambda r: r['total']) / median(sides[1], lambda r: r['total']))]
        out.append('')
    if 'cpu' in results:
        out += course_cpu.markdown(results['cpu'])
    if 'scale' in results:
        out += ['## Scale (1x, the default course on every robot)', '',
                '| robots | simulators | completed | worst true error | control rate: '
                'median / slowest second | total CPU s | holds | target |',
                '|---|---|---|---|---|---|---|---|']
        for r in results['scale']:
            out.append('| %d | %s | %d/%d | %s mm, %s deg | %s Hz / %s ticks | %s | %s | %s |' % (
                r['n'], 'one fake_fleet' if r['mode'] == 'fleet' else 'separate',
                r['completed'], r['n'], fmt(r['true_mm']), fmt(r['true_deg'], '%.2f'),
                fmt(r.get('rate_median')), fmt(r.get('rate_min'), '%.0f'),
                fmt(r['cpu_total'], '%.0f'), 'yes' if r['holds'] else 'no', r['target']))
        out.append('')
    if 'physics' in results:
        phys = results['physics']
        out += ['## The physics robot (MuJoCo) beside the kinematic one', '',
                '| robot | model alone, no ROS | robot alone, lockstep unpaced | '
                'default course at max | final error (ground truth) |',
                '|---|---|---|---|---|']
        for r in phys['robots']:
            out.append('| %s | %s x | %s x | %s x | %s mm, %s deg |' % (
                r['robot'], fmt(r.get('model'), '%.0f'), fmt(r['alone'], '%.0f'),
                fmt(r['course_speedup']),
                fmt(r['error_mm']), fmt(r['heading_deg'], '%+.2f')))
        out += ['', 'Physics robots in one fake_fleet at 1x: up to %s hold (every '
                'course within %g mm, %g deg by its odometry and by ground truth: '
                'about twice what one uncalibrated physics robot misses by).' % (
                    phys['fleet_holds'] or 'none', 1e3 * PHYSICS_LIMITS[0],
                    PHYSICS_LIMITS[1]), '',
                '| robots | completed | worst true error | total CPU s | holds |',
                '|---|---|---|---|---|']
        for r in phys['fleet']:
            out.append('| %d | %d/%d | %s mm, %s deg | %s | %s |' % (
                r['n'], r['completed'], r['n'], fmt(r['true_mm']),
                fmt(r['true_deg'], '%.2f'), fmt(r['cpu_total'], '%.0f'),
                'yes' if r['holds'] else 'no'))
        out.append('')
    return '\n'.join(out)


def plot(results, path):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    panels = [k for k in ('speed', 'scale') if k in results]
    if not panels:
        return
    fig, axes = plt.subplots(1, len(panels), figsize=(6 * len(panels), 4.5), squeeze=False)
    for ax, key in zip(axes[0], panels):
        if key == 'speed':
            for lockstep in (True, False):
                rows = [r for r in results['speed'] if r['lockstep'] == lockstep and r.get('speedup')]
                ax.plot([r['speedup'] for r in rows], [r['error_mm'] for r in rows], 'o-',
                        label='lockstep' if lockstep else 'free-running')
            ax.set_xlabel('achieved speed-up (sim s / wall s)')
            ax.set_ylabel('final position error (mm)')
            ax.set_title('Default course: error vs speed')
        else:
            for mode, label in (('separate', 'separate processes'), ('fleet', 'fake_fleet')):
                rows = [r for r in results['scale'] if r['mode'] == mode]
                ax.plot([r['n'] for r in rows], [r['true_mm'] for r in rows], 'o-', label=label)
            ax.axhline(20.0, color='grey', ls='--', label='20 mm target')
            ax.set_xlabel('robots at 1x')
            ax.set_ylabel('worst final error (mm)')
            ax.set_title('Fleet scale')
        ax.grid(True, alpha=0.3)
        ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=90)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--sections', nargs='+',
                        default=['accuracy', 'speed', 'cpu', 'scale', 'physics'],
                        choices=['accuracy', 'speed', 'cpu', 'scale', 'physics',
                                 'population'],
                        help='population (bench/population.py, its own tables) '
                        'runs only when named: it takes an hour or more')
    parser.add_argument('--runs', type=int, default=10)
    parser.add_argument('--cpu-rounds', type=int, default=3,
                        help='cpu: rounds of (ours, book\'s), about 80 s each')
    parser.add_argument('--speed-against', metavar='WORKSPACE',
                        help='speed: also the CPU per simulated second of the course in '
                        'WORKSPACE (another commit, built with make build WS=...), side by side')
    parser.add_argument('--speed-rounds', type=int, default=3,
                        help='speed: rounds of the CPU per simulated second')
    parser.add_argument('--robots', type=int, nargs='+', default=[1, 10, 20, 40, 80])
    parser.add_argument('--out', default=RESULTS)
    parser.add_argument('--render', action='store_true',
                        help='only redo the table and plot from OUT/latest.json')
    population.add_arguments(parser)
    args = parser.parse_args()
    if 'population' in args.sections:
        args.sections.remove('population')
        print(population.run(args))
        if not args.sections:
            return
    # The sections not run keep their figures from the last run (the
    # table says when each was measured).
    results = {}
    try:
        with open(os.path.join(args.out, 'latest.json')) as f:
            results = json.load(f)
    except (OSError, ValueError):
        pass
    if args.render:
        args.sections = []
    measured = results.setdefault('measured', {})
    if 'accuracy' in args.sections:
        results['accuracy'] = accuracy(args.runs)
    if 'speed' in args.sections:
        results['speed'] = speed()
        results['cpu_per_sim_s'] = cpu_per_sim_s(args.speed_against, args.speed_rounds)
    if 'cpu' in args.sections:
        results['cpu'] = course_cpu.run(args.cpu_rounds)
    if 'scale' in args.sections:
        results['scale'] = scale(args.robots)
    if 'physics' in args.sections:
        results['physics'] = physics(args.robots)
    for section in args.sections:
        measured[section] = time.strftime('%Y-%m-%d %H:%M')
    os.makedirs(args.out, exist_ok=True)
    table = markdown(results)
    with open(os.path.join(args.out, 'latest.md'), 'w') as f:
        f.write(table + '\n\n![bench](latest.png)\n')
    with open(os.path.join(args.out, 'latest.json'), 'w') as f:
        json.dump(results, f, indent=1, default=str)
    plot(results, os.path.join(args.out, 'latest.png'))
    print(table)


if __name__ == '__main__':
    main()
