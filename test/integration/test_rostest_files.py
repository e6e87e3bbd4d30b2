"""Run every test/rostest/*.test and test/faults/*.test file through rostest, one
pytest case each.

This lets `make test` report unit and integration results in one pytest
summary. `catkin_make run_tests` runs the same files through add_rostest().
A file whose verdict the machine's load cannot change runs in any worker,
at a lower priority (test/conftest.py): its graph runs under lockstep at
full speed (`sim_speed" value="max"`), or it says BESIDE (every node that
keeps time is a lockstep member) or NO_CLOCK (no simulated clock, and its
wall-clock waits are deadlines, not measurements). The others, whose
nodes follow the wall clock, run one after another (one xdist group) at
normal priority, so the machine's load cannot make them fall behind.
bench/determinism.py shows which verdicts and figures load changes.
"""
import glob
import os
import subprocess

import pytest

TEST_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ALL_FILES = sorted(glob.glob(os.path.join(TEST_DIR, 'rostest', '*.test'))
                   + glob.glob(os.path.join(TEST_DIR, 'faults', '*.test')))


BESIDE = '<!-- beside other tests: every timed node is a lockstep member -->'
NO_CLOCK = ('<!-- beside other tests: no simulated clock, and its wall-clock waits '
            'are deadlines, not measurements -->')


def _text(path):
    with open(path) as f:
        return f.read()


def beside_others(path):
    text = _text(path)
    return ('<arg name="sim_speed" value="max"/>' in text or BESIDE in text
            or NO_CLOCK in text)


def run_rostest(test_file):
    # Not --text: with it rostest exits 0 even when a test fails.
    proc = subprocess.run(['rostest', test_file],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          universal_newlines=True, timeout=600)
    assert proc.returncode == 0, '%s failed:\n%s' % (
        os.path.basename(test_file), proc.stdout[-6000:])


PARAMS = [pytest.param(f, id=os.path.relpath(f, TEST_DIR),
                       marks=[] if beside_others(f) else [pytest.mark.xdist_group('free_running')])
          for f in ALL_FILES]


@pytest.mark.parametrize('test_file', PARAMS)
def test_rostest(test_file):
    run_rostest(test_file)
