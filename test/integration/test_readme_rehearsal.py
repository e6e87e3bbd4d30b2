"""The README's "rehearse without a robot" block and its PATH line, typed.

The lines are parsed out of README.md and typed, as a user types them, in
shells where another python3 comes first on PATH (a venv without ROS's
modules, test/helpers/other_python.py, as pyenv, conda or a venv put one),
each after the README's ``export PATH=...`` line. The workspace is the
test's own (make test sources it), not the README's ~/.cache one.

- The fake robot stands in a TurtleBot 2: ``fake_turtlebot.launch
  realistic:=true cmd_vel:=mobile_base/commands/velocity``.
- ``calibrate_linear.py`` with /ground_truth as the tape drives it 1 m by
  odometry on the TurtleBot 2's topic. Judged by the robot's ground truth,
  recorded here: it moved, by 1/1.02 of what odometry says (realistic.yaml's
  2 % error) within REALISTIC_TOLERANCE, and the factor the node printed is
  that distance over odometry's, within FACTOR_TOLERANCE.
- The real-robot block's ``rosrun dynamic_reconfigure dynparam set
  /calibrate_linear ...`` line reaches the node after the PATH line (the
  node reports the value), and fails as the issue saw it without the line.

Real time, as a user rehearses: one 1 m leg at 0.15 m/s. Its own master
(started by the typed roslaunch) on a free port; every process it started
is ended at the end, pass or fail.
"""
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import time

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, '..', 'helpers'))
from master import HANG_GUARD, end_processes, wait_for_master  # noqa: E402
from other_python import lacks_rospy, path_with_other_python  # noqa: E402
from ports import free_port  # noqa: E402

pytestmark = [
    pytest.mark.skipif(not shutil.which('roslaunch') or 'ROS_PACKAGE_PATH' not in os.environ,
                       reason='needs a sourced ROS workspace (make test sources one)'),
    # A real-time robot and course: at normal priority, with the
    # free-running rostests.
    pytest.mark.xdist_group('free_running'),
]

README = os.path.join(HERE, '..', '..', 'README.md')
PORTS = range(11506, 11512)
TRUTH_ECHO = [sys.executable, os.path.join(HERE, '..', 'helpers', 'truth_echo.py')]
#: realistic.yaml: odometry says 1.02 m for each true metre.
LINEAR_SCALE_ERROR = 1.02
#: How far true / odometry may be from 1 / LINEAR_SCALE_ERROR: its encoder
#: noise moved the printed factor by 0.11 % (docs/calibration.md); a robot
#: without realistic.yaml's errors is 2 % off.
REALISTIC_TOLERANCE = 0.01
#: The node's ground-truth distance against this test's, both from
#: /ground_truth with the robot still (truth_echo prints 0.01 mm).
TRUTH_TOLERANCE = 0.001  # m
FACTOR_TOLERANCE = 0.001
FACTOR = re.compile(r'odom_linear_scale_correction = measured / odometry = '
                    r'(\S+) / (\S+) = (\S+)')


def section(title):
    with open(README) as f:
        return f.read().split('## ' + title, 1)[1].split('\n## ', 1)[0]


def commands(block):
    lines = (line.split('#')[0].strip() for line in block.splitlines())
    return [line for line in lines if line]


def readme_lines():
    """(the PATH line, the rehearsal's lines, the real-robot block's
    dynparam line for calibrate_linear), as the README has them."""
    path_line, = [line for line in commands(
        re.search(r'```bash\n(.*?)```', section('The lines a ROS user types'), re.S).group(1))
        if line.startswith('export PATH=')]
    blocks = re.findall(r'```bash\n(.*?)```', section('On your real robot'), re.S)
    rehearsal, = [block for block in blocks if block.startswith('# Rehearse without a robot')]
    dynparam, = [line for line in commands(blocks[0])
                 if 'dynparam set /calibrate_linear' in line]
    return path_line, commands(rehearsal), dynparam


class Shells(object):
    """Processes started in shells whose PATH has the stand-in python3
    first, each one's output in a file of its own."""

    def __init__(self, tmp_path):
        self.tmp = tmp_path
        self.path = path_with_other_python(tmp_path / 'venv')
        assert lacks_rospy(self.path)
        port = free_port(PORTS)
        self.env = dict(os.environ, PATH=self.path, PYTHONUNBUFFERED='1',
                        ROS_MASTER_URI='http://localhost:%d' % port, ROS_LOG_DIR=str(tmp_path))
        self.procs = []

    def start(self, log, command, first=None):
        """``command`` (a README line) in a shell that has typed ``first``."""
        shell = '%s; exec %s' % (first, command) if first else 'exec ' + command
        out = open(str(self.tmp / (log + '.log')), 'w')
        proc = subprocess.Popen(['bash', '-c', shell], env=self.env, stdout=out,
                                stderr=subprocess.STDOUT, start_new_session=True)
        self.procs.append(proc)
        return proc

    def run(self, log, command, first=None):
        proc = self.start(log, command, first)
        try:
            proc.wait(HANG_GUARD)
        except subprocess.TimeoutExpired:
            pytest.fail('%s: no end in %.0f s (a hang guard):\n%s' % (
                command, HANG_GUARD, self.output(log)))
        return proc.returncode, self.output(log)

    def output(self, log):
        with open(str(self.tmp / (log + '.log'))) as f:
            return f.read()

    def wait_for(self, ready, what, proc, log):
        """Until ``ready()`` is true, while ``proc`` (logging to ``log``)
        lives; HANG_GUARD wall seconds alive is a hang. Returns ready()."""
        started = time.monotonic()
        while True:
            found = ready()
            if found:
                return found
            assert proc.poll() is None, 'no %s: it ended (exit %s):\n%s' % (
                what, proc.returncode, self.output(log))
            assert time.monotonic() - started < HANG_GUARD, 'no %s after %.0f s alive:\n%s' % (
                what, HANG_GUARD, self.output(log))
            time.sleep(0.1)

    def truth(self):
        """The last ground-truth row (x, y, yaw) truth_echo printed, or None."""
        rows = [line.split()[1:] for line in self.output('truth').splitlines()
                if len(line.split()) == 4 and line.split()[0] == '/']
        return tuple(float(f) for f in rows[-1]) if rows else None

    def close(self):
        end_processes(self.procs, 20)


@pytest.fixture
def shells(tmp_path):
    made = Shells(tmp_path)
    yield made
    made.close()


def test_the_readmes_rehearsal_calibrates_a_stand_in_turtlebot2(shells):
    path_line, (launch, calibrate), dynparam = readme_lines()
    assert 'realistic:=true' in launch and 'cmd_vel:=mobile_base/commands/velocity' in launch
    assert '_ground_truth_topic:=ground_truth' in calibrate
    assert 'cmd_vel:=/mobile_base/commands/velocity' in calibrate

    robot = shells.start('robot', launch, path_line)
    wait_for_master(shells.env['ROS_MASTER_URI'], robot, lambda: shells.output('robot'))
    echo = subprocess.Popen(TRUTH_ECHO, env=dict(shells.env, PATH=os.environ['PATH']),
                            stdout=open(str(shells.tmp / 'truth.log'), 'w'),
                            stderr=subprocess.STDOUT, start_new_session=True)
    shells.procs.append(echo)
    start = shells.wait_for(shells.truth, 'ground truth', robot, 'robot')

    node = shells.start('calibrate', calibrate, path_line)
    found = shells.wait_for(lambda: FACTOR.search(shells.output('calibrate')),
                            'printed factor', node, 'calibrate')
    end = shells.truth()
    said_truth, said_odometry, said_factor = (float(f) for f in found.groups())
    moved = math.hypot(end[0] - start[0], end[1] - start[1])
    print('RESULT rehearsal: the stand-in TurtleBot 2 moved %.4f m by ground truth; the node '
          'printed %s' % (moved, found.group(0)))
    assert moved > 0.9, shells.output('calibrate')
    assert abs(said_truth - moved) < TRUTH_TOLERANCE, (said_truth, moved)
    assert abs(moved / said_odometry * LINEAR_SCALE_ERROR - 1.0) < REALISTIC_TOLERANCE, (
        moved, said_odometry)
    assert abs(said_factor - moved / said_odometry) < FACTOR_TOLERANCE, (said_factor, moved)

    # The README's dynparam line (Debian's dynparam starts with
    # #!/usr/bin/env python3): refused by the stand-in python3, and heard by
    # the node after the PATH line.
    status, out = shells.run('dynparam_without', dynparam)
    assert status != 0 and "No module named 'roslib'" in out, out
    status, out = shells.run('dynparam', dynparam, path_line)
    assert status == 0, out
    given = float(dynparam.split()[-1])
    shells.wait_for(lambda: re.search(r'measured / odometry = %.4f / ' % given,
                                      shells.output('calibrate')),
                    'the given distance reported', node, 'calibrate')

    os.killpg(node.pid, signal.SIGINT)  # Ctrl-C, as the README says
    assert node.wait(HANG_GUARD) == 0, shells.output('calibrate')
