"""make bench's speed section: how fast a course runs, and what each node
costs per simulated second.

The default course at 1x, 10x and max, lockstep and free-running
(free-running "max" is the speed lockstep reached): course wall time,
speed-up, final error. Then the CPU seconds per simulated second of every
node, the default course under lockstep at full speed, ``--speed-rounds``
times; with ``--speed-against WORKSPACE`` (another commit's, built by
``make build WS=...``) that workspace's course after each of ours, side by
side. Run by bench/bench.py (``--sections speed``).
"""
import os
import statistics
import subprocess

from common import fmt, log
from graph import course, describe

#: The target shown beside the lockstep rows (the GUIDE's).
TARGET = 'same end pose at every speed (0.1 mm, 0.01 deg)'


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
                       target=TARGET if lockstep else 'reported')
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


def markdown(rows):
    """The speed table, as lines."""
    out = ['## Speed (default course, ideal robot)', '',
           '| time | asked | course wall time | speed-up | final error | target |',
           '|---|---|---|---|---|---|']
    for r in rows:
        out.append('| %s | %s | %s s | %s x | %s mm, %s deg | %s |' % (
            'lockstep' if r['lockstep'] else 'free-running',
            r['speed'] if r['speed'] == 'max' else r['speed'] + 'x',
            fmt(r['wall_s']), fmt(r.get('speedup')), fmt(r['error_mm'], '%.2f'),
            fmt(r['heading_deg'], '%+.3f'), r['target']))
    out.append('')
    return out


def cpu_markdown(rows):
    """The CPU per simulated second table, as lines."""
    sides = list(dict.fromkeys(r['side'] for r in rows))
    nodes = sorted({n for r in rows for n in r['nodes']},
                   key=lambda n: -max(r['nodes'].get(n, 0.0) for r in rows))
    out = ['## CPU seconds per simulated second (default course, lockstep at full '
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
    return out
