#!/usr/bin/env python3
"""make bench: accuracy, speed, CPU and scale of the courses, in one run.

Every figure comes from the same run on the same machine, so ratios between
rows mean something; absolute times depend on the machine and its load.
Each course runs the way a user runs it: a fresh master, the fake robot
from ``fake_turtlebot.launch`` (or ``fake_turtlebot_ekf.launch``), then
``rosrun rbx1_nav odom_out_and_back.py`` (bench/graph.py); the final error
is read from the simulator's ``ground_truth`` after the course.

Sections (``--sections``, all but population by default), each in the
folder of what it measures:

- accuracy (bench/accuracy/courses.py): ``--runs`` runs each of
  {default, precise} x {ideal, realistic, realistic + pose_ekf}; median
  and max final error.
- speed (bench/speed/courses.py): the default course at 1x, 10x and max,
  lockstep and free-running; then the CPU seconds per simulated second of
  every node, ``--speed-rounds`` times, beside ``--speed-against
  WORKSPACE``'s if given.
- cpu (bench/speed/course_cpu.py): our out-and-back beside the book's own
  script, ``--cpu-rounds`` rounds, free-running at 1x as on a real robot.
- scale (bench/speed/fleet_scale.py): N robots at 1x, separate processes
  and one fake_fleet.
- physics (bench/speed/physics.py): the kinematic and the physics robot
  (MuJoCo) side by side, and how many physics robots one fake_fleet keeps
  at 1x (``--robots``).
- simulator (bench/speed/simulator.py): the fake robot's CPU for one
  default course at 1x, and ``odom_out_and_back_sim.launch
  sim_speed:=max`` from roslaunch to its exit (wall, CPU, the course's
  speed and end pose), ``--sim-rounds`` rounds alternating with each
  ``--sim-against WORKSPACE``.
- determinism (bench/suite/determinism.py): the lockstep course files
  (``--determinism-tests``, default ``lockstep_*.test``) through rostest
  idle, then beside ``--burners`` CPU burners; every figure they print
  must be the same. The suite freezes processes instead
  (lockstep_max_stalled.test), which leaves out what only real load
  does: one thread late against another inside a node, a slow
  rosmaster or rosout. make bench exits 1 if a figure differs.
- population (only when named; bench/population/population.py):
  docs/calibration.md's procedure on ``--population`` robots drawn from
  ``--seed``, its own tables (bench/results/population_*.md).

The test suite's own cost, and the determinism of its other files, are
bench/suite/'s, run on their own. Writes bench/results/latest.md,
latest.json and latest.png, and prints the table. Usage:
make bench [BENCH_ARGS="--sections speed --runs 3"]
"""
import argparse
import json
import os
import sys
import time

from common import RESULTS
from accuracy import courses as accuracy_courses
from population import population
from speed import course_cpu, fleet_scale, physics, simulator
from speed import courses as speed_courses
from suite import determinism

#: Each part of the results and the lines of its table, in latest.md's order.
TABLES = (('accuracy', accuracy_courses.markdown), ('speed', speed_courses.markdown),
          ('cpu_per_sim_s', speed_courses.cpu_markdown), ('cpu', course_cpu.markdown),
          ('scale', fleet_scale.section_markdown), ('physics', physics.markdown),
          ('simulator', simulator.markdown),
          ('determinism', determinism.section_markdown))


def markdown(results):
    measured = results.get('measured', {})
    out = ['# rbx1_nav bench', '',
           'Machine: %d cores, load average %.1f at the end; %s. Measured: %s. '
           'Compare rows within a section, not machines.' % (
               os.cpu_count(), os.getloadavg()[0], time.strftime('%Y-%m-%d %H:%M'),
               ', '.join('%s %s' % kv for kv in sorted(measured.items())) or 'now'), '']
    for key, table in TABLES:
        if key in results:
            out += table(results[key])
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
                        default=['accuracy', 'speed', 'cpu', 'scale', 'physics',
                                 'simulator', 'determinism'],
                        choices=['accuracy', 'speed', 'cpu', 'scale', 'physics',
                                 'simulator', 'determinism', 'population'],
                        help='population (bench/population/population.py, its own tables) '
                        'runs only when named: it takes an hour or more')
    parser.add_argument('--runs', type=int, default=10)
    parser.add_argument('--cpu-rounds', type=int, default=3,
                        help='cpu: rounds of (ours, book\'s), about 80 s each')
    parser.add_argument('--speed-against', metavar='WORKSPACE',
                        help='speed: also the CPU per simulated second of the course in '
                        'WORKSPACE (another commit, built with make build WS=...), side by side')
    parser.add_argument('--speed-rounds', type=int, default=3,
                        help='speed: rounds of the CPU per simulated second')
    parser.add_argument('--robots', type=int, nargs='+', default=[1, 10, 20, 40, 60, 80])
    parser.add_argument('--sim-against', metavar='WORKSPACE', nargs='*', default=[],
                        help='simulator: also these workspaces (other commits, built with '
                        'make build WS=...), rounds alternating')
    parser.add_argument('--sim-rounds', type=int, default=3,
                        help='simulator: rounds, about 45 s per side each')
    parser.add_argument('--determinism-tests', metavar='PATTERN', nargs='+',
                        default=determinism.LOCKSTEP_FILES,
                        help='determinism: the .test files (as bench/suite/determinism.py '
                        '--tests takes them)')
    parser.add_argument('--burners', type=int, default=determinism.SECTION_BURNERS,
                        help='determinism: CPU burners beside the loaded runs')
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
        results['accuracy'] = accuracy_courses.accuracy(args.runs)
    if 'speed' in args.sections:
        results['speed'] = speed_courses.speed()
        results['cpu_per_sim_s'] = speed_courses.cpu_per_sim_s(args.speed_against,
                                                               args.speed_rounds)
    if 'cpu' in args.sections:
        results['cpu'] = course_cpu.run(args.cpu_rounds)
    if 'scale' in args.sections:
        results['scale'] = fleet_scale.section(args.robots)
    if 'physics' in args.sections:
        results['physics'] = physics.physics(args.robots)
    if 'simulator' in args.sections:
        results['simulator'] = simulator.run(args.sim_against, args.sim_rounds)
    if 'determinism' in args.sections:
        results['determinism'] = determinism.section(args.determinism_tests, args.burners)
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
    if 'determinism' in args.sections and not determinism.all_same(results['determinism']):
        sys.exit('bench: determinism: not every figure of the lockstep files was the same '
                 'idle and beside burners (its table above)')


if __name__ == '__main__':
    main()
