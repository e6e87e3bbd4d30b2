"""make bench's cpu section: our out-and-back beside the book's, in CPU seconds.

A course is to cost a user's laptop no more CPU than the book's own
script, its safety included. Each course runs as on a real robot: a fresh ``roscore`` on a
free port, ``rosrun rbx1_nav fake_turtlebot.py`` (free-running at 1x: no
/use_sim_time, no lockstep), then one default out-and-back by either

- ours: the script ``rosrun rbx1_nav odom_out_and_back.py`` runs, default
  parameters, or
- the book's: bench/speed/book/odom_out_and_back.py, ROS By Example's
  listing, its ``import tf`` bench/speed/book/tf.py (tf2_ros underneath,
  as in Noetic).

Both run under bench/speed/modules_at_exit.py (runpy, then the rbx1_nav modules
loaded are written at exit) and as the same ``/usr/bin/python3`` process,
without rosrun's lookup (its CPU is measured once and shown apart). A
course's CPU is its process's whole life (os.wait4: user + system, every
thread); the robot's, the master's and rosout's are their CPU from the
course's start to its exit. Rounds alternate ours and book's, each course
on a fresh master and robot; the figure is the median over rounds of
ours / book's, from the same round.
"""
import json
import math
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
import xmlrpc.client

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
from common import (ROOT, cpu_by_name, descendants, end_processes, free_port,  # noqa: E402
                    ground_truth, log, node_name, wait_for_master)

BOOK = os.path.join(HERE, 'book', 'odom_out_and_back.py')
WRAPPER = os.path.join(HERE, 'modules_at_exit.py')
PYTHON = '/usr/bin/python3'
#: Wall seconds the robot has after its /tf appears before a course starts
#: (the book's script waits 2 s for tf itself; ours waits for it).
SETTLE = 1.0


def wait4(proc):
    """Wait for ``proc``; its CPU seconds (user + system, with its waited
    children's)."""
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = (os.WEXITSTATUS(status) if os.WIFEXITED(status)
                       else -os.WTERMSIG(status))
    return usage.ru_utime + usage.ru_stime


def our_script(env):
    """(path, CPU s): the file ``rosrun rbx1_nav odom_out_and_back.py``
    runs, and the CPU its lookup (bash, catkin_find, find) costs."""
    proc = subprocess.Popen(['rosrun', '--prefix', 'echo', 'rbx1_nav', 'odom_out_and_back.py'],
                            env=env, stdout=subprocess.PIPE, stdin=subprocess.DEVNULL,
                            universal_newlines=True)
    out = proc.stdout.read().strip()
    cpu = wait4(proc)
    if proc.returncode != 0 or not os.path.isfile(out):
        raise RuntimeError('rosrun does not find one odom_out_and_back.py: %r' % out)
    return out, cpu


class Robot(object):
    """A fresh master and fake robot, as a user starts them (in ``env``, a
    workspace's environment; default: this process's)."""

    def __init__(self, env=None):
        port = free_port()
        self.uri = 'http://localhost:%d' % port
        self.env = dict(env or os.environ, ROS_MASTER_URI=self.uri, PYTHONUNBUFFERED='1')
        self.env.pop('ROS_NAMESPACE', None)
        self.groups = []
        self.core = self._start(['roscore', '-p', str(port)])
        wait_for_master(self.uri, self.core)
        self.robot = self._start(['rosrun', 'rbx1_nav', 'fake_turtlebot.py'])

        def tf_up(master):
            publishers = dict(master.getSystemState('/bench')[2][0])
            return '/fake_turtlebot' in publishers.get('/tf', [])
        self._wait(tf_up, 'the robot on /tf')
        time.sleep(SETTLE)

    def _start(self, cmd):
        proc = subprocess.Popen(cmd, env=self.env, stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL, stdin=subprocess.DEVNULL,
                                start_new_session=True)
        self.groups.append(proc)
        return proc

    def _wait(self, ready, what, limit=60.0):
        deadline = time.monotonic() + limit
        while True:
            try:
                if ready(xmlrpc.client.ServerProxy(self.uri)):
                    return
            except OSError:
                pass
            if time.monotonic() > deadline:
                raise RuntimeError('%s not up within %.0f s' % (what, limit))
            time.sleep(0.2)

    def cpu(self):
        """{process: CPU s so far} of the master's processes and the robot."""
        family = descendants(self.core.pid)
        family[self.core.pid] = 'roscore'
        family[self.robot.pid] = 'fake_turtlebot.py'
        return cpu_by_name({pid: node_name(cmdline) for pid, cmdline in family.items()})

    def truth(self):
        """(x, y, yaw) of the robot's next ground_truth message."""
        return ground_truth(self.env)

    def course_env(self, which):
        """The environment a course runs in: the robot's master; for the
        book's script, bench/speed/book/ on PYTHONPATH too (its "import tf")."""
        env = dict(self.env)
        if which == 'book':
            env['PYTHONPATH'] = os.pathsep.join(
                [os.path.dirname(BOOK)] + [p for p in [env.get('PYTHONPATH')] if p])
        return env

    def close(self):
        end_processes(self.groups, 15)


def course(which, script, wall_limit=120.0):
    """One course (``which``: 'ours' or 'book') on a fresh master and robot."""
    robot = Robot()
    workdir = tempfile.mkdtemp(prefix='course_cpu_')
    modules = os.path.join(workdir, 'modules.json')
    env = robot.course_env(which)
    try:
        with open(os.path.join(workdir, 'output'), 'w+') as output:
            before, started = robot.cpu(), time.monotonic()
            proc = subprocess.Popen([PYTHON, WRAPPER, modules, script], env=env,
                                    stdout=output, stderr=subprocess.STDOUT,
                                    stdin=subprocess.DEVNULL, start_new_session=True)
            robot.groups.append(proc)
            timer = _killer(proc, wall_limit)
            cpu = wait4(proc)
            timer.cancel()
            wall = time.monotonic() - started
            after = robot.cpu()
            output.seek(0)
            lines = output.read().splitlines()
        x, y, yaw = robot.truth()
    finally:
        robot.close()
    try:
        with open(modules) as f:
            loaded = [(repo_path(path), lines) for path, lines in json.load(f)]
    except (OSError, ValueError):
        loaded = None
    others = {name: after[name] - before.get(name, 0.0) for name in after}
    return dict(which=which, status=proc.returncode, cpu=cpu, wall=wall,
                others=others, error_mm=1000.0 * math.hypot(x, y),
                heading_deg=math.degrees(yaw), modules=loaded,
                completed=proc.returncode == 0 and (
                    which == 'book' or any('Course complete' in l for l in lines)),
                output=lines[-12:])


def repo_path(path):
    """``path`` from the repository's root when it is in it (the
    workspace links the package's source), else as it is."""
    real = os.path.realpath(path)
    if real.startswith(ROOT + os.sep):
        return os.path.relpath(real, ROOT)
    if '/devel/' in path:  # generated by catkin: the messages, the package's __init__
        return 'devel/' + path.split('/devel/', 1)[1]
    return path


def _killer(proc, seconds):
    """Kill ``proc``'s group after ``seconds`` (a course that hangs)."""
    def kill():
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    timer = threading.Timer(seconds, kill)
    timer.daemon = True
    timer.start()
    return timer


def run(rounds=3):
    """The section's result: every course, and the medians."""
    env = dict(os.environ)
    ours, lookup = our_script(env)
    courses = []
    for i in range(rounds):
        # Alternate which goes first, so neither always follows the other.
        order = ('ours', 'book') if i % 2 == 0 else ('book', 'ours')
        pair = {}
        for which in order:
            result = course(which, ours if which == 'ours' else BOOK)
            result['round'] = i + 1
            log('cpu round %d, %s: %s%.2f CPU s in %.1f s wall; robot %.2f CPU s; '
                'ends %.1f mm, %+.2f deg from the start' % (
                    i + 1, which, '' if result['completed'] else 'FAILED (exit %s) '
                    % result['status'], result['cpu'], result['wall'],
                    result['others'].get('fake_turtlebot', 0.0), result['error_mm'],
                    result['heading_deg']))
            if not result['completed']:
                log('\n'.join('    ' + line for line in result['output']))
            pair[which] = result
            courses.append(result)
        pair['ours']['ratio'] = pair['ours']['cpu'] / pair['book']['cpu']
    ratios = [c['ratio'] for c in courses if 'ratio' in c]
    ok = all(c['completed'] for c in courses)
    modules = next((c['modules'] for c in courses if c['which'] == 'ours' and c['modules']),
                   None)
    book_modules = next((c['modules'] for c in courses if c['which'] == 'book'
                         and c['modules']), None)

    def median(which, key, name=None):
        values = [c[key] if name is None else c[key].get(name, 0.0)
                  for c in courses if c['which'] == which]
        return statistics.median(values)
    summary = dict(
        rounds=rounds, all_completed=ok, median_ratio=statistics.median(ratios),
        ratios=ratios, rosrun_lookup_cpu=lookup, script=ours,
        median={which: dict(cpu=median(which, 'cpu'), wall=median(which, 'wall'),
                            robot=median(which, 'others', 'fake_turtlebot'),
                            rosmaster=median(which, 'others', 'rosmaster'),
                            rosout=median(which, 'others', 'rosout'))
                for which in ('ours', 'book')},
        modules=modules and dict(count=len(modules), lines=sum(n for _, n in modules),
                                 files=sorted(modules, key=lambda m: -m[1])),
        book_modules=book_modules and dict(count=len(book_modules),
                                           lines=sum(n for _, n in book_modules)),
        courses=[{k: v for k, v in c.items() if k != 'modules'} for c in courses])
    log('cpu: median ours / book %.2f (rounds: %s); our node loads %s rbx1_nav modules, '
        '%s lines' % (summary['median_ratio'], ', '.join('%.2f' % r for r in ratios),
                      modules and len(modules), modules and summary['modules']['lines']))
    return summary


def markdown(cpu):
    """The section's table."""
    med = cpu['median']
    out = ['## CPU: our out-and-back beside the book\'s script (1x, free-running)', '',
           'One default out-and-back on a fresh `roscore` and `rosrun rbx1_nav '
           'fake_turtlebot.py` (no /use_sim_time, no lockstep), %d rounds alternating '
           'ours (`rosrun rbx1_nav odom_out_and_back.py`) and the book\'s listing '
           '(bench/speed/book/, tf1 on tf2_ros); CPU s: the course process\'s whole life '
           '(user + system), the others\' over the course. Median ours / book\'s, '
           'from the same round: **%.2f** (rounds: %s).%s' % (
               cpu['rounds'], cpu['median_ratio'],
               ', '.join('%.2f' % r for r in cpu['ratios']),
               '' if cpu['all_completed'] else ' Not every course completed: see '
               'latest.json.'), '',
           '| round | course | exit | course CPU s | wall s | fake_turtlebot CPU s | '
           'rosmaster | rosout | ends (ground truth) |',
           '|---|---|---|---|---|---|---|---|---|']
    for c in cpu['courses']:
        o = c['others']
        out.append('| %d | %s | %s | %.2f | %.1f | %.2f | %.2f | %.2f | %.1f mm, %+.2f deg |' % (
            c['round'], c['which'], c['status'], c['cpu'], c['wall'],
            o.get('fake_turtlebot', 0.0), o.get('rosmaster', 0.0), o.get('rosout', 0.0),
            c['error_mm'], c['heading_deg']))
    for which in ('ours', 'book'):
        m = med[which]
        out.append('| median | %s | | **%.2f** | %.1f | %.2f | %.2f | %.2f | |' % (
            which, m['cpu'], m['wall'], m['robot'], m['rosmaster'], m['rosout']))
    out += ['', 'rosrun\'s own lookup (bash, catkin_find), in neither figure: %.2f CPU s.'
            % cpu['rosrun_lookup_cpu']]
    mods = cpu.get('modules')
    if mods:
        out += ['', 'rbx1_nav modules in our course node\'s sys.modules at exit: **%d, '
                '%d lines** (the book\'s script: %s). By size:' % (
                    mods['count'], mods['lines'],
                    '%d, %d lines' % (cpu['book_modules']['count'],
                                      cpu['book_modules']['lines'])
                    if cpu.get('book_modules') else 'not recorded'), '',
                '| module | lines |', '|---|---|']
        for path, lines in mods['files']:
            out.append('| %s | %d |' % (path, lines))
    out.append('')
    return out


if __name__ == '__main__':
    import argparse
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--rounds', type=int, default=3)
    args = parser.parse_args()
    print('\n'.join(markdown(run(args.rounds))))
