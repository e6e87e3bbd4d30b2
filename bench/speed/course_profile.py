"""Where our out-and-back's CPU goes beside the book's script.

    python3 bench/speed/course_profile.py [--rounds 2] [--rate 500] [--out DIR]

Runs each course as bench/speed/course_cpu.py does (fresh roscore, ``rosrun
rbx1_nav fake_turtlebot.py``, 1x, free-running), ours and the book's
alternating, twice a round: under bench/speed/thread_cpu.py (each thread's CPU
seconds, from /proc: exact) and under ``py-spy record --format raw --gil
--nonblocking`` (py-spy on PATH: ``python3 -m pip install py-spy``). It
prints, for ours and the book's, the CPU per thread, then py-spy's samples
by thread, by function with what it calls, and by function alone.

py-spy's own idle detection counts threads blocked in recv, sleep or a
condition as running here, so only samples of the thread holding the GIL
are kept: Python code running (work in C with the GIL released, a
socket's recv, is left out). Samples, not seconds: a sample is 1/--rate s.
The raw stacks stay in OUT (default a temporary directory) for flame graphs.
"""
import argparse
import collections
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
from speed import course_cpu  # noqa: E402

FRAME = re.compile(r'^(?P<func>.*) \((?P<file>[^()]*?)(?::(?P<line>\d+))?\)$')


def short(path):
    """A frame's file, shortened: from the package's source or a site dir."""
    for mark in ('/src/rbx1_nav/', '/dist-packages/', '/lib/python3.11/'):
        if mark in path:
            return path.split(mark, 1)[1]
    return path


def parse(path):
    """[(frames root first, count)] of a py-spy raw file."""
    stacks = []
    with open(path) as f:
        for line in f:
            line = line.rstrip('\n')
            if not line:
                continue
            body, _, count = line.rpartition(' ')
            frames = []
            for raw in body.split(';'):
                m = FRAME.match(raw)
                if m is None:  # "process ..." / "thread ..." headers
                    continue
                frames.append('%s (%s%s)' % (m.group('func'), short(m.group('file')),
                                             ':' + m.group('line') if m.group('line') else ''))
            stacks.append((frames, int(count)))
    return stacks


def thread_of(frames):
    """The thread a stack ran in, named by its outermost function of note."""
    if not frames:
        return '?'
    if frames[0].startswith('<module> '):
        return 'main thread'
    if not frames[0].startswith('Thread._bootstrap '):  # a _thread's
        return without_line(frames[0])
    for frame in frames:
        if frame.split(' (', 1)[0] in ('Thread._bootstrap', 'Thread._bootstrap_inner',
                                       'Thread.run'):
            continue
        return without_line(frame)
    return frames[-1]


def without_line(frame):
    """A frame without its line number: a function, wherever it is in it."""
    func, _, where = frame.partition(' (')
    return '%s (%s' % (func, where.rsplit(':', 1)[0] + ')' if ':' in where else where)


def summary(stacks, top=25):
    total = sum(n for _, n in stacks)
    threads = collections.Counter()
    inclusive = collections.Counter()
    own = collections.Counter()
    for frames, n in stacks:
        threads[thread_of(frames)] += n
        for func in {without_line(f) for f in frames}:
            inclusive[func] += n
        if frames:
            own[without_line(frames[-1])] += n
    out = ['%d samples' % total, '', 'by thread:']
    out += ['  %6d %5.1f%%  %s' % (n, 100.0 * n / total, t) for t, n in threads.most_common()]
    out += ['', 'by function, with what it calls (top %d):' % top]
    out += ['  %6d %5.1f%%  %s' % (n, 100.0 * n / total, f)
            for f, n in inclusive.most_common(top)]
    out += ['', 'by function alone (top %d):' % top]
    out += ['  %6d %5.1f%%  %s' % (n, 100.0 * n / total, f) for f, n in own.most_common(top)]
    return '\n'.join(out)


def profiled(which, script, rate, out):
    """One course under py-spy; the raw file's path and the course's CPU s."""
    robot = course_cpu.Robot()
    env = robot.course_env(which)
    raw = os.path.join(out, '%s_%d.txt' % (which, int(time.time() * 1000)))
    try:
        proc = subprocess.run(
            ['py-spy', 'record', '--format', 'raw', '--gil', '--nonblocking', '--rate', str(rate),
             '--output', raw, '--', course_cpu.PYTHON, script], env=env,
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=180)
    finally:
        robot.close()
    return raw, proc.returncode


def threads(which, script, out):
    """One course under bench/speed/thread_cpu.py: {thread: CPU s}."""
    robot = course_cpu.Robot()
    env = robot.course_env(which)
    path = os.path.join(out, '%s_threads_%d.json' % (which, int(time.time() * 1000)))
    try:
        subprocess.run([course_cpu.PYTHON, os.path.join(HERE, 'thread_cpu.py'), path, script],
                       env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                       timeout=180)
    finally:
        robot.close()
    with open(path) as f:
        return json.load(f)


def thread_table(runs):
    """Median CPU s per thread over ``runs`` ({thread: CPU s} each)."""
    names = sorted({n for run in runs for n in run},
                   key=lambda n: -statistics.median(r.get(n, 0.0) for r in runs))
    out = ['CPU s per thread (median of %d courses; total %.2f):' % (
        len(runs), statistics.median(sum(r.values()) for r in runs))]
    out += ['  %6.2f  %s' % (statistics.median(r.get(n, 0.0) for r in runs), n)
            for n in names]
    return '\n'.join(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--rounds', type=int, default=2)
    parser.add_argument('--rate', type=int, default=500, help='samples per second')
    parser.add_argument('--out', default=None)
    args = parser.parse_args()
    out = args.out or tempfile.mkdtemp(prefix='course_profile_')
    os.makedirs(out, exist_ok=True)
    ours, _ = course_cpu.our_script(dict(os.environ))
    files = {'ours': [], 'book': []}
    per_thread = {'ours': [], 'book': []}
    for i in range(args.rounds):
        for which in (('ours', 'book') if i % 2 == 0 else ('book', 'ours')):
            script = ours if which == 'ours' else course_cpu.BOOK
            raw, status = profiled(which, script, args.rate, out)
            sys.stderr.write('%s: py-spy exit %s, %s\n' % (which, status, raw))
            files[which].append(raw)
            per_thread[which].append(threads(which, script, out))
    for which in ('ours', 'book'):
        stacks = [s for raw in files[which] if os.path.exists(raw) for s in parse(raw)]
        print('=== %s (%d courses; py-spy at %d Hz, samples holding the GIL; raw '
              'stacks: %s)' % (which, len(files[which]), args.rate, ' '.join(files[which])))
        print(thread_table(per_thread[which]))
        print()
        print(summary(stacks))
        print()


if __name__ == '__main__':
    main()
