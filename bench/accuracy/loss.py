#!/usr/bin/env python3
"""How many precise courses ride out 20 % packet loss: a distribution.

Runs the fault suite's 20 % loss case (test/faults/test_two_hosts.py::
test_twenty_percent_loss_precise_courses_ride_it_out: precise courses at
once, a fleet on one network namespace, the courses on another, every
connection over a link that drops a fifth of its packets) ``--runs`` times
with ``--courses`` courses (RBX1_LOSS_COURSES; ``make test`` runs fewer)
and reads the figure it prints: how many ended within 5 mm and 0.5 deg of
the ideal end pose by ground truth. Loss is random by nature, so that count
is measured here, as a distribution, and not asserted in ``make test``
(which keeps what must hold every run: each course completes or gives up
with one line, every robot stands still at the end, and each completed
course reports the end pose its robot really stands at). Needs root
(network namespaces). Not a test: run it on demand, e.g.

    python3 bench/accuracy/loss.py --runs 20

(source the workspace first, as `make bench` does). Prints, and writes to
bench/results/loss.md, each run's count and the distribution.
"""
import argparse
import collections
import os
import re
import statistics
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from common import RESULTS, ROOT  # noqa: E402

CASE = ('test/faults/test_two_hosts.py::'
        'test_twenty_percent_loss_precise_courses_ride_it_out')
RESULT = re.compile(r'RESULT 20 % loss, (\d+) precise courses .*?: (\d+) within')


def one_run(limit, courses):
    """(courses, within 5 mm / 0.5 deg, passed, wall s, output) of one run
    of ``courses`` courses."""
    start = time.monotonic()
    proc = subprocess.run(
        [sys.executable, '-m', 'pytest', CASE, '-q', '-s', '-p', 'no:cacheprovider'],
        cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
        universal_newlines=True, timeout=limit,
        env=dict(os.environ, RBX1_LOSS_COURSES=str(courses)))
    found = RESULT.search(proc.stdout)
    if found is None:
        return None, None, proc.returncode == 0, time.monotonic() - start, proc.stdout
    return (int(found.group(1)), int(found.group(2)), proc.returncode == 0,
            time.monotonic() - start, proc.stdout)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--runs', type=int, default=20)
    parser.add_argument('--courses', type=int, default=10,
                        help='precise courses at once in each run')
    parser.add_argument('--limit', type=float, default=900.0,
                        help='wall seconds one run may take')
    parser.add_argument('--out', default=os.path.join(RESULTS, 'loss.md'))
    args = parser.parse_args()
    if os.geteuid() != 0:
        sys.exit('bench/accuracy/loss.py needs root: the link is two network namespaces')
    counts, lines = [], []
    for run in range(1, args.runs + 1):
        courses, good, passed, wall, text = one_run(args.limit, args.courses)
        if courses is None:
            line = 'run %d: no RESULT line (%s, %.0f s):\n%s' % (
                run, 'passed' if passed else 'failed', wall, text[-2000:])
        else:
            counts.append(good)
            line = 'run %d: %d of %d within 5 mm / 0.5 deg; test %s; %.0f s' % (
                run, good, courses, 'passed' if passed else 'FAILED', wall)
        print(line, flush=True)
        lines.append(line)
    histogram = collections.Counter(counts)
    table = ['# Precise courses at 20 % loss', '',
             '%s, %d runs of `python3 bench/accuracy/loss.py` (%d courses each).' % (
                 time.strftime('%Y-%m-%d %H:%M'), args.runs, args.courses), '',
             '| within 5 mm / 0.5 deg by ground truth (of %d) | runs |' % args.courses,
             '|---|---|']
    table += ['| %d | %d |' % (k, histogram[k]) for k in sorted(histogram, reverse=True)]
    if counts:
        table += ['', 'min %d, median %g, max %d of %d.' % (
            min(counts), statistics.median(counts), max(counts), args.courses)]
    table += ['', '```'] + lines + ['```']
    os.makedirs(os.path.dirname(args.out), exist_ok=True)
    with open(args.out, 'w') as f:
        f.write('\n'.join(table) + '\n')
    print('\n'.join(table[:-len(lines) - 2]))


if __name__ == '__main__':
    main()
