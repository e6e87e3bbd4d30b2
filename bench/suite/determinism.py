#!/usr/bin/env python3
"""Does a rostest's verdict depend on the machine? Each test idle, then loaded.

Runs each test/rostest/*.test and test/faults/*.test file (``--tests``
picks some) through ``rostest FILE`` twice: once as it is, once beside
``--burners`` CPU burners (``yes > /dev/null``, started and killed here),
and compares the figures the test printed. A test whose figures differ
between the two runs depends on its machine's load: under lockstep a
course must end in the same pose to the last printed digit however busy
the machine is.

Figures. rostest keeps each test node's stdout in its result file
(``$ROS_HOME/test_results/<package>/rosunit-<test-name>.xml``, system-out;
each run here has a ROS_HOME of its own). Every number in every line a
test node prints is a figure: its name is the text just before it, with
the node's test-name and the line's first words (``RESULT Ed``); it is
compared as printed, so the precision a test prints is the precision
compared. The lines of the two runs are paired by their text with the
numbers taken out (and paths, such as a temporary directory, too), in
order; a line only one run printed is listed as such. Log lines
(``[INFO] [wall, sim]: ...``) lose their time stamps first; one printed
into the middle of another line is taken out of it as a line of its own.

Wall-clock figures. A figure that measures wall time (a latency in wall
seconds, a speed ratio) is meant to change with the load and is listed
apart, not compared. The convention: such a figure's unit, the text right
after the number up to the next ``,``, ``;``, ``:``, ``=`` or
``name=``, says
``wall``: ``gave up 5.02 s (wall time) after``, ``exit=1 after 3.41 s
wall; ...``, ``(0.52 s in the same wall time before it)``. A test that
prints a wall-clock figure writes ``wall`` there, and nothing else does.

The "idle" run is only as idle as the shared machine is: the load average
is shown with each run. ``--burners 0`` runs each test twice as it is:
what differs then is scatter from run to run, whatever the load. Not a
test: run it on demand (source the workspace first, as `make bench`
does), e.g.

    python3 bench/suite/determinism.py --tests courses.test umbmark.test
    python3 bench/suite/determinism.py      # every file: slow

Before and after a change, on one machine: ``--save before.json`` at the
old commit (each test once), then ``--against before.json`` at the new one.

Prints, per test, "same" or the figures that differ (idle, loaded), and a
summary table; ``--out FILE`` writes the same as markdown.

`make bench` runs it as its determinism section (:func:`section`) on the
lockstep course files, beside four burners, and exits 1 unless every
figure is the same: the real load that lockstep_max_stalled.test's
frozen processes stand in for in the suite.
"""
import argparse
import glob
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from common import ROOT, end_processes  # noqa: E402
from suite.suite_cpu import LIMIT, rostest_env, rostest_files  # noqa: E402

NUMBER = re.compile(r'(?<![\w./])[-+]?(?:nan|inf|(?:\d+(?:\.\d+)?|\.\d+)(?:[eE][-+]?\d+)?)'
                    r'(?!\w|\.\d)')
PATH = re.compile(r'(?<![\w/])/[^\s,;:)\'"]+')
LOG_STAMP = re.compile(r'^\[\s*(DEBUG|INFO|WARN|ERROR|FATAL)\s*\]\s*\[[^\]]*\]:\s*')
#: Where a log line starts inside another line: a node's log output and a
#: test's print share one stdout, so a log line can land mid-line.
LOG_START = re.compile(r'(?=\[\s*(?:DEBUG|INFO|WARN|ERROR|FATAL)\s*\]\s*\[[\d.,\s]*\]:)')
UNIT_END = re.compile(r'[,;:=]|\s[\w.]+=')
WALL = re.compile(r'\bwall\b', re.IGNORECASE)


def node_outputs(ros_home):
    """{test-name: [line, ...]}: each test node's stdout, from its result file."""
    outputs = {}
    for path in sorted(glob.glob(os.path.join(ros_home, 'test_results', '*',
                                              'rosunit-*.xml'))):
        name = os.path.basename(path)[len('rosunit-'):-len('.xml')]
        try:
            text = ET.parse(path).getroot().findtext('system-out') or ''
        except ET.ParseError:
            with open(path, errors='replace') as f:
                found = re.search(r'<system-out>(.*?)</system-out>', f.read(), re.S)
            text = found.group(1) if found else ''
        text = text.replace('<![CDATA[', '').replace(']]>', '')
        outputs[name] = [part.strip() for line in text.splitlines()
                         for part in LOG_START.split(line) if part.strip()]
    return outputs


def figures(lines):
    """[(key, label, value, wall)] of every number in lines.

    key pairs a figure with its twin in another run: (template, its
    occurrence among lines of that template, index in the line)."""
    found, seen = [], {}
    for line in lines:
        line = LOG_STAMP.sub('', line)
        template = NUMBER.sub('#', PATH.sub('<path>', line))
        occurrence = seen.get(template, 0)
        seen[template] = occurrence + 1
        head = ' '.join(re.split(r'[:(]', NUMBER.split(line)[0])[0].split()[:3])
        previous = 0
        for index, match in enumerate(NUMBER.finditer(line)):
            words = line[previous:match.start()].strip(' ,;:)%').split()
            context = ''
            while words and len(context) + len(words[-1]) < 32:
                context = (words.pop() + ' ' + context).strip()
            unit = UNIT_END.split(NUMBER.split(line[match.end():])[0])[0]
            if index and head and not context.startswith(head):
                context = head + ' ... ' + context
            found.append(((template, occurrence, index), '%s # %s' % (
                context, ' '.join(unit.split()[:3])), match.group(0),
                bool(WALL.search(unit))))
            previous = match.end()
    return found


def compare(idle, loaded):
    """(same, differ, wall, only_idle, only_loaded) of two runs' outputs.

    same: count; differ and wall: [(node, label, idle value, loaded value)];
    only_*: [(node, line)] printed by one run only."""
    same, differ, wall, only_idle, only_loaded = 0, [], [], [], []
    for node in sorted(set(idle) | set(loaded)):
        a = {key: (label, value, w) for key, label, value, w in figures(idle.get(node, []))}
        b = {key: (label, value, w) for key, label, value, w in figures(loaded.get(node, []))}
        for key in sorted(set(a) & set(b), key=lambda k: (k[1], k[0], k[2])):
            label, value, is_wall = a[key]
            if is_wall:
                wall.append((node, label, value, b[key][1]))
            elif value == b[key][1]:
                same += 1
            else:
                differ.append((node, label, value, b[key][1]))
        lines_a = {key[:2] for key in a}
        lines_b = {key[:2] for key in b}
        only_idle += [(node, t.replace('#', '…')) for t, _ in sorted(lines_a - lines_b)]
        only_loaded += [(node, t.replace('#', '…')) for t, _ in sorted(lines_b - lines_a)]
    return same, differ, wall, only_idle, only_loaded


def run_rostest(test):
    """(passed, wall s, {node: lines}, output tail, 1-min load at the end)."""
    home = tempfile.mkdtemp(prefix='determinism_')
    start = time.monotonic()
    try:
        with tempfile.TemporaryFile(mode='w+') as log:
            proc = subprocess.Popen(['rostest', test], cwd=ROOT, env=rostest_env(home),
                                    stdout=log, stderr=subprocess.STDOUT,
                                    universal_newlines=True, start_new_session=True)
            try:
                code = proc.wait(timeout=LIMIT)
            except subprocess.TimeoutExpired:
                end_processes([proc], 30)
                code = None
            except BaseException:
                end_processes([proc], 30)
                raise
            log.seek(0)
            tail = log.read()[-3000:]
        return (code == 0, time.monotonic() - start, node_outputs(home), tail,
                os.getloadavg()[0])
    finally:
        shutil.rmtree(home, ignore_errors=True)


def start_burners(n):
    return [subprocess.Popen(['yes'], stdout=subprocess.DEVNULL) for _ in range(n)]


def kill(procs):
    for proc in procs:
        proc.kill()
        proc.wait()


def idle_and_loaded(test, burners):
    """(idle, loaded): :func:`run_rostest` of ``test`` as it is, then beside
    ``burners`` CPU burners."""
    idle = run_rostest(test)
    burning = start_burners(burners)
    try:
        loaded = run_rostest(test)
    finally:
        kill(burning)
    return idle, loaded


def verdict(idle, loaded, compared):
    """A test's verdict from its two runs and :func:`compare` of them."""
    same, differ, _, only_idle, only_loaded = compared
    if not (idle[0] and loaded[0]):
        return 'failed'
    if differ or only_idle or only_loaded:
        return 'differs (%d of %d)' % (len(differ), same + len(differ))
    if same:
        return 'same (%d figure%s)' % (same, '' if same == 1 else 's')
    return 'no figures'


#: make bench's determinism section: the lockstep course files, whose
#: stalls stand in for load in the suite (lockstep_max_stalled.test says
#: what they leave out), beside real CPU burners.
LOCKSTEP_FILES = ['lockstep_*.test']
SECTION_BURNERS = 4


def section(patterns=None, burners=SECTION_BURNERS):
    """make bench's determinism section: each file (``patterns``, default
    LOCKSTEP_FILES) idle and beside ``burners`` burners; a row each."""
    rows = []
    for test in rostest_files(patterns or LOCKSTEP_FILES):
        idle, loaded = idle_and_loaded(test, burners)
        compared = compare(idle[2], loaded[2])
        rows.append({'test': test, 'burners': burners,
                     'verdict': verdict(idle, loaded, compared),
                     'runs': [[r[0], round(r[1], 1), round(r[4], 1)] for r in (idle, loaded)],
                     'differ': compared[1], 'only_idle': compared[3],
                     'only_loaded': compared[4], 'wall_figures': len(compared[2]),
                     'failed_output': [r[3] for r in (idle, loaded) if not r[0]]})
        print('determinism: %s: %s' % (test, rows[-1]['verdict']), flush=True)
    return rows


def all_same(rows):
    """True if every row's figures were the same idle and loaded."""
    return bool(rows) and all(r['verdict'].startswith('same') for r in rows)


def section_markdown(rows):
    """The section's table, as lines."""
    out = ['## Determinism (lockstep files idle, then beside %s CPU burners)'
           % (rows[0]['burners'] if rows else '?'), '',
           '| test | verdict | idle | loaded | wall-clock figures (not compared) |',
           '|---|---|---|---|---|']
    for r in rows:
        out.append('| %s | %s | %s | %s | %d |' % (
            r['test'], r['verdict'], *('%s %.1f s (load %.1f)' % (
                'pass' if ok else 'FAIL', wall, load) for ok, wall, load in r['runs']),
            r['wall_figures']))
    notes = []
    for r in rows:
        for node, label, a, b in r['differ']:
            notes.append('- %s, %s: %s: idle %s, loaded %s' % (r['test'], node, label, a, b))
        for which in ('only_idle', 'only_loaded'):
            for node, line in r[which]:
                notes.append('- %s, %s: only the %s run printed `%s`'
                             % (r['test'], node, which[5:], line))
    out += [''] + notes if notes else []
    for r in rows:
        for tail in r['failed_output']:
            out += ['', 'A run of %s failed; the end of its output:' % r['test'], '', '```']
            out += tail.strip().splitlines()[-15:] + ['```']
    out.append('')
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--tests', metavar='PATTERN', nargs='+',
                        help='only the .test files a PATTERN names (a path, a file name, '
                             'a part of the path, or a shell pattern: "faults/*.test")')
    parser.add_argument('--burners', type=int, default=2,
                        help='CPU burners (yes > /dev/null) beside the loaded run')
    parser.add_argument('--out', help='also write the report, as markdown, here')
    parser.add_argument('--save', metavar='JSON',
                        help="write each test's figures (its idle run) here, for --against")
    parser.add_argument('--against', metavar='JSON',
                        help='compare each test once, as it is, with the figures --save '
                             'wrote at another commit, instead of idle against loaded: '
                             'a change that keeps lockstep deterministic keeps them all')
    # --save runs each test once and compares nothing.
    args = parser.parse_args()
    saved = {}
    if args.against:
        with open(args.against) as f:
            saved = json.load(f)
    tests = rostest_files(args.tests)
    if not tests:
        sys.exit('determinism: no .test file matches %r' % args.tests)
    report, summary = [], []

    def say(line=''):
        print(line, flush=True)
        report.append(line)

    say('# Figures against %s' % args.against if args.against else
        '# Figures idle and beside %d CPU burners' % args.burners)
    say()
    say('%s, `python3 bench/suite/determinism.py%s`, %d cores, load average %.2f at the start.'
        % (time.strftime('%Y-%m-%d %H:%M'), ''.join(' ' + a for a in sys.argv[1:]),
           os.cpu_count(), os.getloadavg()[0]))
    for test in tests:
        if args.against:  # the saved run is "idle", this one "loaded"
            if test not in saved:
                say()
                say('## %s: not in %s' % (test, args.against))
                continue
            idle = (True, 0.0, saved[test], '', 0.0)
            loaded = run_rostest(test)
        else:
            idle = run_rostest(test)
            if args.save:  # one run, kept for a later --against
                saved[test] = idle[2]
                with open(args.save, 'w') as f:
                    json.dump(saved, f, indent=1)
                say('%s: %s, %d figures saved' % (test, 'pass' if idle[0] else 'FAIL',
                                                  len(figures(sum(idle[2].values(), [])))))
                continue
            burners = start_burners(args.burners)
            try:
                loaded = run_rostest(test)
            finally:
                kill(burners)
        compared = compare(idle[2], loaded[2])
        _, differ, wall, only_idle, only_loaded = compared
        runs = 'idle %s %.1f s (load %.1f), loaded %s %.1f s (load %.1f)' % (
            'pass' if idle[0] else 'FAIL', idle[1], idle[4],
            'pass' if loaded[0] else 'FAIL', loaded[1], loaded[4])
        outcome = verdict(idle, loaded, compared)
        summary.append((test, outcome, len(wall)))
        say()
        say('## %s: %s' % (test, outcome))
        say()
        say(runs + '.')
        for name, result in (('idle', idle), ('loaded', loaded)):
            if not result[0]:
                say()
                say('The %s run failed; the end of its output:' % name)
                say()
                say('```')
                say(result[3].strip())
                say('```')
        if differ:
            say()
            say('| node | figure | idle | loaded |')
            say('|---|---|---|---|')
            for row in differ:
                say('| %s | %s | %s | %s |' % row)
        for name, lines in (('idle', only_idle), ('loaded', only_loaded)):
            for node, line in lines:
                say()
                say('Only the %s run printed (%s): `%s`' % (name, node, line))
        if wall:
            say()
            say('Wall-clock figures (not compared): ' + '; '.join(
                '%s: %s %s, %s' % (node, label, a, b) for node, label, a, b in wall))
    say()
    say('## Summary')
    say()
    say('| test | verdict | wall-clock figures (not compared) |')
    say('|---|---|---|')
    for row in summary:
        say('| %s | %s | %d |' % row)
    if args.out:
        with open(args.out, 'w') as f:
            f.write('\n'.join(report) + '\n')


if __name__ == '__main__':
    main()
