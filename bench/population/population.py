#!/usr/bin/env python3
"""The calibration procedure (docs/calibration.md) on a population of robots.

``make bench BENCH_ARGS="--sections population"`` draws ``--population``
robots (100) from ``--seed`` (1), each built wrong the way TurtleBot-class
hardware is (:data:`RANGES`), and takes every robot through that
procedure unattended, with the nodes a user runs and the simulator's
``ground_truth`` as the tape measure:

1. the out-and-back course, book mode then precise mode (before);
2. ``calibrate_linear.py`` then ``calibrate_angular.py``; their printed
   factors set on the robot's driver (``odom_*_scale_correction``), the
   driver restarted;
3. ``umbmark.py`` (``--umbmark-runs`` squares each way, the docs' 5);
   the course in book mode and in precise mode (scale factors only);
4. the multipliers UMBmark printed, if it supports a correction, set on
   the driver, the driver restarted, and the two courses again (after;
   without a correction the scale-only courses are the after ones).

Each course's error is the true distance and heading between where it
started and where the robot stands 1 s after it ended. Every robot runs
on ``--models``: ``physics`` (the MuJoCo TurtleBot, fake_turtlebot.py
~physics) and ``kinematic`` (the kinematic robot in
``config/realistic.yaml``'s realistic mode, the cheap reference).

The robots run in ``--lanes`` lanes at once, each lane a master of its
own with sim_clock.launch at full speed under lockstep and its robots one
after another, so a robot's figures depend on its seed only, not on the
machine's load or on which lane ran it. Writes
``bench/results/population_<model>.{md,csv,png}`` and prints the table.
"""
import argparse
import csv
import json
import os
import signal
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from common import RESULTS, ROOT, end_processes  # noqa: E402

BOOK = (0.01, 3.0)  # m, deg: the book's "less than 1 cm ... a few degrees"
MODELS = ('physics', 'kinematic')

#: The parameters drawn for each robot: (low, high) of a uniform draw, or
#: the choices (equally likely), and why that range. They are assumptions
#: about TurtleBot-class hardware, stated so they can be argued with, not
#: measurements of a fleet.
RANGES = {
    # A rubber tyre's rolling radius moves with tread wear and the load on
    # it; +-1.5 % per wheel gives linear factors within about 1.5 % of 1,
    # the book's "a percent or two".
    'left_wheel_radius_error': ((0.985, 1.015), 'each wheel +-1.5 %: tread wear and load'),
    'right_wheel_radius_error': ((0.985, 1.015), 'each wheel +-1.5 %: tread wear and load'),
    # Where a tyre about 2 cm wide touches the floor moves across its
    # width: +-1 cm on a 26 cm base would be +-4 %; +-3 % is taken.
    'wheel_base_error': ((0.97, 1.03), 'wheel base +-3 %: the tyres\' contact width'),
    'floor': (('carpet', 'tile'), 'carpet or tile, half each (rbx1_nav.sim.floors)'),
    # The URDF's 6 kg base, alone or with a laptop and a sensor on it.
    'mass': ((6.0, 8.0), 'physics: 6 kg base plus up to 2 kg of laptop and sensor'),
    'motor_deadband': ((0.1, 0.3), 'physics: 0.1-0.3 rad/s of wheel speed the motors do not turn at'),
    # An iRobot Create's encoders, or a Kobuki's.
    'encoder_ticks': ((508.8, 2578.33), 'physics: a Create\'s or a Kobuki\'s encoder ticks per turn'),
    'encoder_noise': ((0.001, 0.003), 'kinematic: realistic.yaml\'s 0.002 m/sqrt(m) +-50 %'),
}


def draw(n, seed):
    """``n`` robots from ``seed``: a list of {'id', drawn parameters}."""
    rng = np.random.default_rng(seed)
    robots = []
    for k in range(n):
        robot = {'id': k + 1, 'seed': int(rng.integers(1, 2 ** 31))}
        for name, (spec, _) in sorted(RANGES.items()):
            if isinstance(spec[0], str) or name == 'encoder_ticks':
                robot[name] = spec[int(rng.integers(len(spec)))]
            else:
                robot[name] = round(float(rng.uniform(*spec)), 5)
        robots.append(robot)
    return robots


def settings(robot, model):
    """The fake robot's private parameters for ``robot`` on ``model``."""
    wheels = {'left_wheel_radius_error': robot['left_wheel_radius_error'],
              'right_wheel_radius_error': robot['right_wheel_radius_error'],
              'seed': robot['seed']}
    if model == 'physics':
        return dict(wheels, physics=True, floor=robot['floor'], mass=robot['mass'],
                    motor_deadband=robot['motor_deadband'],
                    encoder_ticks=robot['encoder_ticks'],
                    wheel_separation_error=robot['wheel_base_error'])
    import yaml
    with open(os.path.join(ROOT, 'config', 'realistic.yaml')) as f:
        values = yaml.safe_load(f)
    # The kinematic robot's wheel base error is its angular_scale_error
    # (odometry turns that much too far); its radii carry the distance error.
    values.update(wheels, linear_scale_error=1.0,
                  angular_scale_error=robot['wheel_base_error'],
                  encoder_noise=robot['encoder_noise'])
    return values


def true_factors(robot):
    """The geometric truths of what the procedure should print:
    odom_linear_scale_correction, odom_angular_scale_correction (true /
    odometry, turning in place) and UMBmark's Ed. The physics robot's
    wheels slip and scrub as well (by a few tenths of a percent on carpet,
    test_physics_umbmark.py), which the geometry leaves out."""
    mean = 2.0 / (1.0 / robot['left_wheel_radius_error']
                  + 1.0 / robot['right_wheel_radius_error'])
    return {'true_linear': mean, 'true_angular': mean / robot['wheel_base_error'],
            'true_ed': robot['right_wheel_radius_error'] / robot['left_wheel_radius_error']}


def physics_model(robot, **driver):
    """``robot`` on its MuJoCo model without ROS, at rest at time 0, with
    the ``driver`` settings (fake_turtlebot.py's, e.g. the scale factors
    set on it) over its own."""
    from rbx1_nav.sim.physics import PhysicsConfig, PhysicsFleet
    config = {k: v for k, v in settings(robot, 'physics').items() if k != 'physics'}
    sim = PhysicsFleet(1, PhysicsConfig(**dict(config, **driver))).robot(0)
    sim.fleet.step(0.0)
    return sim


def model_factors(robot, period=0.05):
    """The physics robot's own truths, measured on its MuJoCo model without
    ROS: true over odometry distance for a 1 m drive by odometry at 0.15
    m/s, and true over odometry turn for a 360 deg turn in place by
    odometry at 0.5 rad/s (calibrate_linear's and calibrate_angular's
    defaults), each commanded every ``period`` s and followed by 1 s at
    rest. Rolling on a loaded tyre and scrubbing in a turn are in them, as
    on a real robot; the geometry (:func:`true_factors`) leaves them out."""
    import math
    found = {}
    for name, (v, w) in (('model_linear', (0.15, 0.0)), ('model_angular', (0.0, 0.5))):
        sim = physics_model(robot)
        now = 0.0
        truth0, odom0 = sim.truth, sim.odom
        odometry = truth = 0.0
        rest = None
        while rest is None or now < rest:
            moving = rest is None
            sim.command(v if moving else 0.0, w if moving else 0.0, now)
            now += period
            before_truth, before_odom = sim.truth, sim.odom
            sim.fleet.step(now)
            if w:
                odometry += math.remainder(sim.odom.yaw - before_odom.yaw, 2 * math.pi)
                truth += math.remainder(sim.truth.yaw - before_truth.yaw, 2 * math.pi)
                done = odometry >= 2 * math.pi
            else:
                odometry = math.hypot(sim.odom.x - odom0.x, sim.odom.y - odom0.y)
                truth = math.hypot(sim.truth.x - truth0.x, sim.truth.y - truth0.y)
                done = odometry >= 1.0
            if moving and done:
                rest = now + 1.0
        found[name] = truth / odometry
    return found


#: Wall seconds a node of the procedure may take before it is taken for
#: hung: the figures do not depend on it (lockstep), so it is generous for
#: a machine loaded many times over.
NODE_WALL_LIMIT = 1200.0


# -- one lane: a master of its own, its robots one after another ----------

def run_robot(robot, model, umbmark_runs, watch, workdir, short=False):
    """The procedure on one robot; a dict of its figures. ``umbmark_runs``
    0 leaves UMBmark out; ``short`` (a test's form) runs the precise course
    after the procedure only."""
    import unittest
    from course_harness import FakeRobot, calibrate, course_end_error
    checks = unittest.TestCase()  # the harness's assertions, outside a test
    row = dict(robot, model=model, **true_factors(robot))
    base = settings(robot, model)

    def course(name, **params):
        dist, heading = course_end_error(checks, watch, rest=1.0,
                                         wall_limit=NODE_WALL_LIMIT, **params)
        row[name + '_mm'], row[name + '_deg'] = round(1e3 * dist, 2), round(heading, 3)

    fake = FakeRobot.restart(None, watch, base)
    try:
        if not short:
            course('before_book')
            course('before_precise', precise='true')
        row['linear'] = calibrate(checks, 'linear', NODE_WALL_LIMIT)[0]
        row['angular'] = calibrate(checks, 'angular', NODE_WALL_LIMIT)[0]
        scaled = dict(base, odom_linear_scale_correction=row['linear'],
                      odom_angular_scale_correction=row['angular'])
        fake = FakeRobot.restart(fake, watch, scaled)
        factors = umbmark_runs and run_umbmark(row, umbmark_runs, workdir)
        if not short:
            course('scaled_book')
            course('scaled_precise', precise='true')
        if factors:
            multipliers = ('left_wheel_radius_multiplier', 'right_wheel_radius_multiplier',
                           'wheel_separation_multiplier')
            fake = FakeRobot.restart(fake, watch, dict(
                scaled, **{name: factors[name] for name in multipliers}))
            if not short:
                course('after_book')
            course('after_precise', precise='true')
        elif short:
            course('after_precise', precise='true')
        else:
            # UMBmark changed nothing: the courses just run are the after ones.
            for mode in ('book', 'precise'):
                for unit in ('mm', 'deg'):
                    row['after_%s_%s' % (mode, unit)] = row['scaled_%s_%s' % (mode, unit)]
    except (AssertionError, OSError, RuntimeError):
        if not fake.running() and not fake.log.closed:  # not closed here: say so
            print('robot %d: its simulator had ended (exit %d) before this failure. %s'
                  % (robot['id'], fake.proc.returncode, fake.tail()), flush=True)
        raise
    finally:
        fake.close()
    return row


def run_umbmark(row, runs, workdir):
    """umbmark.py with ground truth as the tape; its Ed and Eb into ``row``;
    returns the corrections it supports (None if none)."""
    import unittest
    import yaml
    from umbmark_test import umbmark
    results = os.path.join(workdir, 'umbmark_%s_%d.yaml' % (row['model'], row['id']))
    status, output = umbmark({'runs': runs, 'side': 1.0, 'run_pause': 0.0,
                              'ground_truth_topic': 'ground_truth',
                              'results': results, 'plot': ''},
                             NODE_WALL_LIMIT)
    unittest.TestCase().assertEqual(status, 0, output)
    with open(results) as f:
        found = yaml.safe_load(f)
    row['ed'], row['eb'] = found['ed'], found['eb']
    row['umbmark_supported'] = bool(found.get('corrections'))
    return found.get('corrections')


def lane(job, out):
    """Run the robots of ``job`` (a JSON file) on a master of this
    process's own; append one JSON row per robot to ``out``."""
    sys.path[:0] = [os.path.join(ROOT, 'test', 'helpers'), os.path.join(ROOT, 'test', 'rostest')]
    from graph import Master
    with open(job) as f:
        job = json.load(f)
    # A lane stopped (the bench interrupted) still closes its robot,
    # clock and master: SIGTERM unwinds through the finally clauses.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(1))
    master = Master()
    # Between two nodes of the procedure only the robot is a member: at
    # sim_clock's idle speed (10x by default) it steps 500 times a wall
    # second for nothing (this lane waits in wall time: its node started
    # before /use_sim_time was set).
    clock = subprocess.Popen(['roslaunch', 'rbx1_nav', 'sim_clock.launch', 'sim_speed:=max',
                              'idle_speed:=1'],
                             env=master.env, stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL, start_new_session=True)
    from course_harness import RobotWatch, wait_until
    # A robot reads /use_sim_time and /lockstep once, as it starts: not
    # before the launch has set them (it would run on wall time, and its
    # course refuse it). However long that takes, while the launch lives.
    wait_until(lambda: master.rospy.has_param('/lockstep') or clock.poll() is not None,
               NODE_WALL_LIMIT)
    if not master.rospy.has_param('/lockstep'):
        raise RuntimeError('sim_clock.launch set no /lockstep: it %s'
                           % ('ended (exit %d)' % clock.returncode if clock.poll() is not None
                              else 'hung for %.0f s' % NODE_WALL_LIMIT))
    watch = RobotWatch()
    workdir = tempfile.mkdtemp(prefix='population_')
    try:
        for robot in job['robots']:
            started = time.monotonic()
            try:
                row = run_robot(robot, job['model'], job['umbmark_runs'], watch, workdir,
                                job['short'])
            except (AssertionError, OSError, RuntimeError) as e:
                print('robot %d failed:\n%s' % (robot['id'], e), flush=True)  # the lane's log
                row = dict(robot, model=job['model'], failed=str(e).splitlines()[0][:300])
            row['wall_s'] = round(time.monotonic() - started, 1)
            with open(out, 'a') as f:
                f.write(json.dumps(row) + '\n')
    finally:
        end_processes([clock], 30)
        master.close()


# -- the population: lanes, table, plot ----------------------------------

def run_model(robots, model, lanes, umbmark_runs, log=print, short=False):
    """Every robot on ``model`` in ``lanes`` lanes (:func:`run_robot`'s
    ``umbmark_runs`` and ``short``); rows ordered by id."""
    workdir = tempfile.mkdtemp(prefix='population_%s_' % model)
    procs, outs = [], []
    for k in range(lanes):
        job, out = (os.path.join(workdir, 'lane%d.%s' % (k, ext)) for ext in ('json', 'rows'))
        with open(job, 'w') as f:
            json.dump({'model': model, 'umbmark_runs': umbmark_runs, 'short': short,
                       'robots': robots[k::lanes]}, f)
        open(out, 'w').close()
        log_file = open(os.path.join(workdir, 'lane%d.log' % k), 'w')
        procs.append(subprocess.Popen([sys.executable, os.path.abspath(__file__),
                                       '--lane', job, out],
                                      stdout=log_file, stderr=subprocess.STDOUT))
        outs.append(out)
    done = set()
    try:
        while any(p.poll() is None for p in procs):
            time.sleep(2.0)
            for row in read_rows(outs):
                if row['id'] not in done:
                    done.add(row['id'])
                    log('%s %d/%d done, %s' % (model, len(done), len(robots), describe(row)))
    finally:
        for proc in procs:  # interrupted: the lanes clean up after them
            if proc.poll() is None:
                proc.terminate()
                proc.wait()
    rows = read_rows(outs)
    if len(rows) < len(robots):
        log('%s: %d of %d robots have no row: see the lane logs in %s'
            % (model, len(robots) - len(rows), len(robots), workdir))
    return sorted(rows, key=lambda r: r['id'])


STAGES = (('before_book', 'before, book mode'), ('before_precise', 'before, precise mode'),
          ('scaled_book', 'scale factors only, book mode'),
          ('scaled_precise', 'scale factors only, precise mode'),
          ('after_book', 'after, book mode'), ('after_precise', 'after, precise mode'))


def read_rows(outs):
    rows = []
    for out in outs:
        with open(out) as f:
            rows.extend(json.loads(line) for line in f if line.strip())
    return rows


def describe(row):
    """One line on one robot's figures."""
    if 'failed' in row:
        return 'robot %d failed: %s' % (row['id'], row['failed'])
    parts = ['%s %.1f mm %.2f deg' % (label, row[name + '_mm'], row[name + '_deg'])
             for name, label in STAGES if name + '_mm' in row]
    return 'robot %d: %s (%.0f s)' % (row['id'], '; '.join(parts), row['wall_s'])


def within_book(row, name):
    return row[name + '_mm'] < 1e3 * BOOK[0] and row[name + '_deg'] < BOOK[1]


def quantiles(values):
    """(median, 90th percentile, worst)."""
    return (float(np.median(values)), float(np.percentile(values, 90)), max(values))


def markdown(rows, model, args, wall):
    ok = [r for r in rows if 'failed' not in r]
    lines = ['### %s robots (%d drawn from seed %d)' % (model, len(rows), args.seed), '',
             'Command: `make bench BENCH_ARGS="--sections population --models %s '
             '--population %d --seed %d --lanes %d --umbmark-runs %d"`; %s wall on %d cores '
             '(%d lanes).' % (model, args.population, args.seed, args.lanes,
                               args.umbmark_runs, minutes(wall), os.cpu_count(), args.lanes),
             '']
    failed = [r for r in rows if 'failed' in r]
    if failed:
        lines += ['%d robots failed a step: %s' % (len(failed), '; '.join(
            'robot %d: %s' % (r['id'], r['failed']) for r in failed)), '']
    if not ok:
        return '\n'.join(lines + ['No robot went through the procedure: no table. '
                                   'The lane logs say why.'])
    lines += ['| stage | position mm: median | 90 % | worst | heading deg: median | 90 % '
              '| worst | within 1 cm and 3 deg |', '|---|---|---|---|---|---|---|---|']
    for name, label in STAGES:
        mm = quantiles([r[name + '_mm'] for r in ok])
        deg = quantiles([r[name + '_deg'] for r in ok])
        lines.append('| %s | %.1f | %.1f | %.1f | %.2f | %.2f | %.2f | %d of %d |' % (
            (label,) + mm + deg + (sum(within_book(r, name) for r in ok), len(ok))))
    lines += ['', '| printed factor, off the truth in % | median | 90 % | worst |',
              '|---|---|---|---|']
    pairs = [('linear, against the geometry', 'linear', 'true_linear'),
             ('angular, against the geometry', 'angular', 'true_angular'),
             ('UMBmark Ed, against the wheels', 'ed', 'true_ed')]
    if all('model_linear' in r for r in ok):
        pairs[2:2] = [('linear, against the robot\'s own (model_factors)', 'linear', 'model_linear'),
                      ('angular, against the robot\'s own (model_factors)', 'angular',
                       'model_angular')]
    for label, printed, true in pairs:
        off = [100 * abs(r[printed] / r[true] - 1) for r in ok if r.get(printed)]
        if off:
            lines.append('| %s | %.3f | %.3f | %.3f |' % ((label,) + quantiles(off)))
    lines.append('')
    lines.append('UMBmark supported a correction on %d of %d robots.' % (
        sum(r['umbmark_supported'] for r in ok), len(ok)))
    lines += [''] + causes(ok, model)
    worst = sorted(ok, key=lambda r: -r['after_precise_mm'])[:5]
    own = ('floor', 'encoder ticks') if model == 'physics' else ('encoder noise',)
    lines += ['', 'The five largest errors after the procedure, precise mode:', '',
              '| robot | after, precise | after, book | Ed (true) | wheel base | %s |'
              % ' | '.join(own), '|---|---|---|---|---|' + '---|' * len(own)]
    for r in worst:
        cells = ((r['floor'], '%g' % r['encoder_ticks']) if model == 'physics'
                 else ('%g' % r['encoder_noise'],))
        lines.append('| %d | %.1f mm %.2f deg | %.1f mm %.2f deg | %.4f | %.3f | %s |' % (
            r['id'], r['after_precise_mm'], r['after_precise_deg'], r['after_book_mm'],
            r['after_book_deg'], r['true_ed'], r['wheel_base_error'], ' | '.join(cells)))
    return '\n'.join(lines)


#: What may explain a robot's remaining error: name, value of a row.
CAUSES = (
    ('wheel mismatch |Ed - 1|', lambda r: abs(r['true_ed'] - 1)),
    ('wheel base error |b - 1|', lambda r: abs(r['wheel_base_error'] - 1)),
    ('mean wheel error |r - 1|', lambda r: abs(r['true_linear'] - 1)),
    ('floor (tile 1, carpet 0)', lambda r: float(r['floor'] == 'tile')),
    ('mass', lambda r: r['mass']),
    ('motor deadband', lambda r: r['motor_deadband']),
    ('encoder ticks', lambda r: r['encoder_ticks']),
    ('encoder noise', lambda r: r['encoder_noise']),
)


def ranks(values):
    order = np.argsort(values, kind='stable')
    out = np.empty(len(values))
    out[order] = np.arange(len(values))
    return out


def causes(rows, model):
    """Lines of a table: each parameter's rank correlation (Spearman's, ties
    broken by order) with the error after the procedure, per mode; a
    parameter the model does not have, or that does not vary, is left out."""
    used = [c for c in CAUSES if not (model == 'physics' and c[0] == 'encoder noise')
            and not (model == 'kinematic' and c[0] in ('floor (tile 1, carpet 0)', 'mass',
                                                      'motor deadband', 'encoder ticks'))]
    lines = ['| robot parameter | rank correlation with the error after: book mode '
             '| precise mode |', '|---|---|---|']
    for label, value in used:
        x = ranks([value(r) for r in rows])
        cells = []
        for mode in ('book', 'precise'):
            y = ranks([r['after_%s_mm' % mode] for r in rows])
            cells.append('%+.2f' % np.corrcoef(x, y)[0, 1] if x.std() and y.std() else '-')
        lines.append('| %s | %s | %s |' % ((label,) + tuple(cells)))
    return lines


def minutes(seconds):
    return '%d:%02d' % divmod(int(round(seconds)), 60)


def plot(rows, model, path):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    ok = [r for r in rows if 'failed' not in r]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for name, label in STAGES:
        for ax, unit in zip(axes, ('mm', 'deg')):
            values = sorted(r['%s_%s' % (name, unit)] for r in ok)
            ax.plot(values, np.arange(1, len(values) + 1) / len(values), label=label)
    for ax, unit, limit in zip(axes, ('position error, mm', 'heading error, deg'),
                               (1e3 * BOOK[0], BOOK[1])):
        ax.axvline(limit, color='k', linestyle=':')
        ax.set_xscale('log')
        ax.set_xlabel(unit)
        ax.set_ylabel('share of robots')
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle('Out-and-back on %d %s robots, by ground truth (dotted: the book\'s '
                 '1 cm, 3 deg)' % (len(ok), model))
    fig.tight_layout()
    fig.savefig(path, dpi=80)


def write(rows, model, args, wall):
    if model == 'physics':
        for row in rows:
            if 'failed' not in row and 'model_linear' not in row:
                row.update(model_factors(row))
    os.makedirs(args.out, exist_ok=True)
    stem = os.path.join(args.out, 'population_%s' % model)
    keys = sorted({k for r in rows for k in r})
    with open(stem + '.csv', 'w', newline='') as f:
        writer = csv.DictWriter(f, keys)
        writer.writeheader()
        writer.writerows(rows)
    table = markdown(rows, model, args, wall)
    with open(stem + '.md', 'w') as f:
        f.write(table + '\n\n![%s population](population_%s.png)\n' % (model, model))
    plot(rows, model, stem + '.png')
    return table


def differences(rows, path):
    """[(robot, figure, here, there)] of the figures of ``rows`` that
    differ from the same robots' in the CSV file ``path`` (an earlier run)."""
    with open(path, newline='') as f:
        earlier = {int(row['id']): row for row in csv.DictReader(f)}
    found = []
    for row in rows:
        there = earlier.get(row['id'])
        if there is None:
            continue
        for key in sorted(set(row) & set(there) - {'wall_s'}):
            if str(row[key]) != there[key]:
                found.append((row['id'], key, row[key], there[key]))
    return found


def add_arguments(parser):
    parser.add_argument('--population', type=int, default=100, help='robots drawn')
    parser.add_argument('--seed', type=int, default=1, help='the draw\'s seed')
    parser.add_argument('--models', nargs='+', default=list(MODELS), choices=MODELS)
    parser.add_argument('--lanes', type=int, default=2, help='masters running at once')
    parser.add_argument('--umbmark-runs', type=int, default=5, help='UMBmark squares each way')
    parser.add_argument('--against', metavar='DIR', help='print every figure that differs '
                        'from the same robots\' in DIR/population_<model>.csv (an '
                        'earlier run: the same seed must give the same figures)')


def run(args, log=print):
    """Every model in ``args.models``; the tables, one after another."""
    robots = draw(args.population, args.seed)
    tables = []
    for model in args.models:
        started = time.monotonic()
        rows = run_model(robots, model, args.lanes, args.umbmark_runs, log)
        tables.append(write(rows, model, args, time.monotonic() - started))
        if args.against:
            earlier = os.path.join(args.against, 'population_%s.csv' % model)
            found = differences(rows, earlier)
            tables.append('\n'.join(['%s robot %d: %s %s here, %s in %s' % (
                model, robot, key, here, there, earlier) for robot, key, here, there in found])
                or 'Every figure of the %d %s robots equals %s\'s.' % (len(rows), model, earlier))
    return '\n\n'.join(tables)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    add_arguments(parser)
    parser.add_argument('--out', default=RESULTS)
    parser.add_argument('--lane', nargs=2, metavar=('JOB', 'OUT'), help=argparse.SUPPRESS)
    parser.add_argument('--rows', nargs='+', metavar='FILE',
                        help='only write the tables of one model from the lanes\' row '
                        'files (laneK.rows) of a run stopped early, its robots with '
                        'every lower id done; --wall gives its wall seconds')
    parser.add_argument('--wall', type=float, default=0.0, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.lane:
        lane(*args.lane)
    elif args.rows:
        rows = sorted(read_rows(args.rows), key=lambda r: r['id'])
        ids = [r['id'] for r in rows]
        rows = rows[:next((k for k, i in enumerate(ids) if i != k + 1), len(ids))]
        args.population = len(rows)
        print(write(rows, args.models[0], args, args.wall))
    else:
        print(run(args))


if __name__ == '__main__':
    main()
