#!/usr/bin/env python3
"""CPU seconds of each part of `make test`: which tests the suite's time goes to.

Runs every test/rostest/*.test and test/faults/*.test file one at a time
through ``rostest FILE`` (as test/integration/test_rostest_files.py does),
then the pytest parts: test/unit as one row, and each file of
test/integration (but test_rostest_files.py, which is the rostest rows) and
test/faults/test_*.py as a row of its own. Per row: the result, wall
seconds, and CPU seconds (user + system) of the whole process tree.

The CPU figure is this process's RUSAGE_CHILDREN before and after the row.
That counts a process once its parent reaps it, and a parent's figure
includes what it reaped: roslaunch (rostest) reaps its nodes. A process
whose parent ends first would be re-parented to init and lost, so this
tool makes itself a child subreaper (prctl PR_SET_CHILD_SUBREAPER): such
orphans come to it, and it reaps them. Processes still running
``--grace`` seconds after the row ends are killed (SIGKILL), reaped,
counted and shown in the row ("N left over"). Each rostest has a
ROS_HOME of its own (a temporary directory), so its results and logs
collide with no other run on the machine.

On a shared machine wall seconds depend on the neighbours; CPU seconds
much less, so the rows are sorted by CPU. The header gives the load
average before and after, and each row the 1-minute load average at its
end. Not a test: run it on demand (source the workspace first, as `make
bench` does), e.g.

    python3 bench/suite/suite_cpu.py --out bench/results/suite_cpu.md
    python3 bench/suite/suite_cpu.py --tests nav_square --no-pytest

Prints the markdown table and writes it to ``--out``.
"""
import argparse
import ctypes
import fnmatch
import glob
import os
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from common import RESULTS, ROOT, end_processes  # noqa: E402
import ros_etc  # noqa: E402  (test/helpers, on the path by common)
PR_SET_CHILD_SUBREAPER = 36
#: The wall seconds one rostest may take (test_rostest_files.py's limit).
LIMIT = 600.0


def rostest_files(patterns=None):
    """The .test files `make test` runs through rostest, relative to ROOT;
    with patterns, those that match one."""
    files = sorted(glob.glob(os.path.join(ROOT, 'test', 'rostest', '*.test'))
                   + glob.glob(os.path.join(ROOT, 'test', 'faults', '*.test')))
    files = [os.path.relpath(f, ROOT) for f in files]
    if patterns:
        files = [f for f in files if any(matches(f, p, files) for p in patterns)]
    return files


def matches(name, pattern, names=()):
    """A shell pattern the path ends with (``faults/*.test``), or a plain
    substring of the path; a pattern that is one of names (or the file
    name of one) picks that name alone: ``courses.test`` is not
    physics_courses.test."""
    if any(c in pattern for c in '*?['):
        return fnmatch.fnmatch(name, '*' + pattern)  # the end of the path
    if any(pattern in (n, os.path.basename(n)) for n in names):
        return pattern in (name, os.path.basename(name))
    return pattern in name


def pytest_parts():
    """(row name, pytest arguments) of the pytest parts of `make test`."""
    parts = [('pytest test/unit', ['test/unit'])]
    for path in sorted(glob.glob(os.path.join(ROOT, 'test', 'integration', 'test_*.py'))
                       + glob.glob(os.path.join(ROOT, 'test', 'faults', 'test_*.py'))):
        rel = os.path.relpath(path, ROOT)
        if os.path.basename(rel) != 'test_rostest_files.py':
            parts.append(('pytest ' + rel, [rel]))
    return parts


def become_subreaper():
    """Orphans of our descendants come to us (Linux 3.4+); False if refused."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0) == 0
    except (OSError, AttributeError):
        return False


def children_cpu():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def our_children():
    """Pids of the live processes whose parent is this one."""
    me, found = os.getpid(), []
    for entry in os.listdir('/proc'):
        if not entry.isdigit():
            continue
        try:
            with open('/proc/%s/stat' % entry) as f:
                fields = f.read().rsplit(')', 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == me and fields[0] != 'Z':
            found.append(int(entry))
    return found


def reap():
    """Reap every child that has ended (the orphans that came to us)."""
    while True:
        try:
            pid, _ = os.waitpid(-1, os.WNOHANG)
        except ChildProcessError:
            return
        if pid == 0:
            return


def collect_leftovers(grace):
    """Reap orphans; kill those still running after ``grace`` s. Their count."""
    deadline = time.monotonic() + grace
    while True:
        reap()
        alive = our_children()
        if not alive or time.monotonic() > deadline:
            break
        time.sleep(0.1)
    for pid in alive:
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    for pid in alive:
        try:
            os.waitpid(pid, 0)
        except ChildProcessError:
            pass
    return len(alive)


def run_measured(argv, env=None, limit=LIMIT, grace=5.0):
    """Run argv to its end; (returncode or None on timeout, output, wall s,
    CPU s of the tree, leftover processes)."""
    cpu0, start = children_cpu(), time.monotonic()
    # A file, not a pipe: a process left over holding the pipe would keep
    # a reader waiting past the end of the run.
    with tempfile.TemporaryFile(mode='w+') as log:
        proc = subprocess.Popen(argv, cwd=ROOT, env=env, stdout=log,
                                stderr=subprocess.STDOUT, universal_newlines=True,
                                start_new_session=True)
        try:
            code = proc.wait(timeout=limit)
        except subprocess.TimeoutExpired:
            end_processes([proc], 30)  # SIGINT: rostest passes it on
            code = None
        except BaseException:  # Ctrl-C: take the run down with us
            end_processes([proc], 30)
            raise
        log.seek(0)
        out = log.read()
    wall = time.monotonic() - start
    leftovers = collect_leftovers(grace)
    return code, out, wall, children_cpu() - cpu0, leftovers


def rostest_env(ros_home):
    env = dict(os.environ, ROS_HOME=ros_home, PYTHONUNBUFFERED='1')
    env.pop('ROS_NAMESPACE', None)
    return env


def outcome(code, leftovers):
    text = 'timeout' if code is None else ('pass' if code == 0 else 'FAIL')
    return text + (' (%d left over)' % leftovers if leftovers else '')


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--tests', metavar='PATTERN', nargs='+',
                        help='only the .test files (and pytest rows) a PATTERN names (a path, a '
                             'file name, a part of the path, or a shell pattern: "faults/*.test")')
    parser.add_argument('--no-pytest', action='store_true', help='the rostest files only')
    parser.add_argument('--no-rostest', action='store_true', help='the pytest parts only')
    parser.add_argument('--grace', type=float, default=5.0,
                        help='seconds a leftover process gets before it is killed')
    parser.add_argument('--out', default=os.path.join(RESULTS, 'suite_cpu.md'))
    args = parser.parse_args()
    if not become_subreaper():
        sys.stderr.write('suite_cpu: cannot become a subreaper; orphans CPU is lost\n')
    # The rows' launches read roscore.xml's answers as make test's do
    # (test/conftest.py); the two rosversion runs that make them, here, are
    # the only CPU the table leaves out (about 0.1 s).
    ros_etc.use_answered_etc()
    load_before = os.getloadavg()
    try:
        commit = subprocess.run(['git', 'rev-parse', '--short', 'HEAD'], cwd=ROOT,
                                stdout=subprocess.PIPE, universal_newlines=True).stdout.strip()
    except OSError:
        commit = '?'
    started = time.strftime('%Y-%m-%d %H:%M')
    rows = []  # (name, result, wall, cpu, load)

    def record(name, code, out, wall, cpu, leftovers):
        load = os.getloadavg()[0]
        rows.append((name, outcome(code, leftovers), wall, cpu, load))
        sys.stderr.write('%-55s %-8s %6.1f s wall %7.1f s CPU  load %.1f\n' % (
            name, outcome(code, leftovers), wall, cpu, load))
        if code != 0:
            sys.stderr.write(out[-3000:] + '\n')

    if not args.no_rostest:
        for test in rostest_files(args.tests):
            home = tempfile.mkdtemp(prefix='suite_cpu_')
            try:
                record(test, *run_measured(['rostest', test], env=rostest_env(home),
                                           grace=args.grace))
            finally:
                shutil.rmtree(home, ignore_errors=True)
    if not args.no_pytest:
        for name, paths in pytest_parts():
            if args.tests and not any(matches(p, t) for p in paths for t in args.tests):
                continue
            record(name, *run_measured(
                [sys.executable, '-m', 'pytest'] + paths + ['-q', '-p', 'no:cacheprovider'],
                limit=3600.0, grace=args.grace))
    load_after = os.getloadavg()
    rows.sort(key=lambda r: -r[3])
    rostest_cpu = sum(r[3] for r in rows if not r[0].startswith('pytest '))
    pytest_cpu = sum(r[3] for r in rows if r[0].startswith('pytest '))
    total_cpu = rostest_cpu + pytest_cpu
    lines = [
        '# CPU seconds of the test suite, one part at a time', '',
        '%s, commit %s, `python3 bench/suite/suite_cpu.py%s`: %d cores, load average '
        '(1, 5, 15 min) %.2f %.2f %.2f before, %.2f %.2f %.2f after (the machine '
        'is shared: wall seconds depend on the neighbours, CPU seconds much less).' % (
            started, commit, ''.join(' ' + a for a in sys.argv[1:]), os.cpu_count(),
            load_before[0], load_before[1], load_before[2],
            load_after[0], load_after[1], load_after[2]), '',
        'CPU = user + system seconds of the whole process tree. Sorted by CPU.', '',
        '| test | result | wall s | CPU s | load at end |', '|---|---|---|---|---|']
    lines += ['| %s | %s | %.1f | %.1f | %.1f |' % r for r in rows]
    lines += ['| **total** (%d rows) | %d pass | %.1f | %.1f | |' % (
        len(rows), sum(r[1].startswith('pass') for r in rows),
        sum(r[2] for r in rows), total_cpu), '',
        'rostest files %.1f CPU s, pytest parts %.1f CPU s; on %d cores the suite '
        'needs at least %.0f s of wall time however it is spread.' % (
            rostest_cpu, pytest_cpu, os.cpu_count(), total_cpu / os.cpu_count())]
    text = '\n'.join(lines) + '\n'
    if args.out:
        os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
        with open(args.out, 'w') as f:
            f.write(text)
    print(text)


if __name__ == '__main__':
    main()
