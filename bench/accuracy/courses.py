"""make bench's accuracy section: where the out-and-back ends, by ground truth.

``--runs`` runs each of {default, precise} x {ideal, realistic, realistic +
pose_ekf}, lockstep at full speed (pose_ekf, no lockstep member, at
:data:`graph.POSE_EKF_SPEED` x); realistic runs use seeds 1..runs. Median
and max final error. Run by bench/bench.py (``--sections accuracy``).
"""
import statistics

from common import fmt, log
from graph import POSE_EKF_SPEED, course, describe

#: Targets shown beside the ideal robot's rows (the GUIDE's).
TARGETS = {
    'default': 'within 20 mm, 2.5 deg (ideal)',
    'precise': 'within 3 mm, 0.3 deg (ideal)',
}


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


def markdown(rows):
    """The section's table, as lines."""
    out = ['## Accuracy (lockstep at full speed, pose_ekf rows at %sx; final error '
           'on ground truth)' % POSE_EKF_SPEED, '',
           '| course | robot | completed | median | max | target |',
           '|---|---|---|---|---|---|']
    for r in rows:
        out.append('| %s | %s | %d/%d | %s mm, %s deg | %s mm, %s deg | %s |' % (
            r['mode'], r['setup'], r['completed'], r['runs'], fmt(r['median_mm']),
            fmt(r['median_deg'], '%.2f'), fmt(r['max_mm']), fmt(r['max_deg'], '%.2f'),
            r['target']))
    out.append('')
    return out
