"""Run every test/*.test and test/faults/*.test file through rostest, one
pytest case each.

This lets `make test` report unit and integration results in one pytest
summary. `catkin_make run_tests` runs the same files through add_rostest().
The files whose graph runs under lockstep at full speed
(`sim_speed" value="max"`), or that say BESIDE (every node that keeps time
is a lockstep member), cannot fall behind their clock, so they are
collected by test_rostest_files_lockstep.py, which `make test` runs in
two workers beside the other pytest suites; the others, whose nodes follow
a free-running clock, run here after that, one at a time (one xdist
group), beside nothing but the light two-host tests.
"""
import glob
import os
import subprocess

import pytest

TEST_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ALL_FILES = sorted(glob.glob(os.path.join(TEST_DIR, '*.test'))
                   + glob.glob(os.path.join(TEST_DIR, 'faults', '*.test')))


BESIDE = '<!-- beside other tests: every timed node is a lockstep member -->'


def _text(path):
    with open(path) as f:
        return f.read()


def at_full_speed(path):
    return '<arg name="sim_speed" value="max"/>' in _text(path)


def lockstep_only(path):
    return at_full_speed(path) or BESIDE in _text(path)


LOCKSTEP_FILES = [f for f in ALL_FILES if lockstep_only(f)]
TEST_FILES = [f for f in ALL_FILES if not lockstep_only(f)]


def run_rostest(test_file):
    # Not --text: with it rostest exits 0 even when a test fails.
    proc = subprocess.run(['rostest', test_file],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          universal_newlines=True, timeout=600)
    assert proc.returncode == 0, '%s failed:\n%s' % (
        os.path.basename(test_file), proc.stdout[-6000:])


@pytest.mark.xdist_group('free_running')
@pytest.mark.parametrize('test_file', TEST_FILES,
                         ids=[os.path.relpath(f, TEST_DIR) for f in TEST_FILES])
def test_rostest(test_file):
    run_rostest(test_file)
