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
normal priority, so the machine's load cannot make them fall behind. A
file whose test starts RViz says RVIZ and runs in the xdist group of
test/integration/test_rviz_views.py: one RViz at a time.
bench/suite/determinism.py shows which verdicts and figures load changes.
"""
import glob
import os
import re
import subprocess

import pytest

TEST_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ALL_FILES = sorted(glob.glob(os.path.join(TEST_DIR, 'rostest', '*.test'))
                   + glob.glob(os.path.join(TEST_DIR, 'faults', '*.test')))


BESIDE = '<!-- beside other tests: every timed node is a lockstep member -->'
NO_CLOCK = ('<!-- beside other tests: no simulated clock, and its wall-clock waits '
            'are deadlines, not measurements -->')
#: Two RViz at once on a loaded machine can crash one of them (an abort
#: inside RViz, or a SIGSEGV at its start).
RVIZ = '<!-- starts RViz: one RViz at a time, in the xdist group rviz -->'


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


def group(path):
    """The xdist group ``path`` runs in: None for any worker."""
    if RVIZ in _text(path):
        return 'rviz'
    return None if beside_others(path) else 'free_running'


PARAMS = [pytest.param(f, id=os.path.relpath(f, TEST_DIR),
                       marks=[pytest.mark.xdist_group(group(f))] if group(f) else [])
          for f in ALL_FILES]


@pytest.mark.parametrize('test_file', PARAMS)
def test_rostest(test_file):
    run_rostest(test_file)


#: rostest's time-limit is a hang guard, never a verdict: a test that ends
#: in seconds idle may take many times that beside other work.
HANG_GUARD = 300


def test_every_time_limit_is_a_hang_guard():
    for path in ALL_FILES:
        text = _text(path)  # and the test's own files it includes
        for name in re.findall(r'\$\(find rbx1_nav\)/test/([^"]+\.xml)"', text):
            text += _text(os.path.join(TEST_DIR, name))
        limits = [float(v) for v in re.findall(r'time-limit="([^"]+)"', text)]
        assert limits and min(limits) >= HANG_GUARD, (path, limits)


def test_every_rostest_that_starts_rviz_says_so():
    """A .test whose test script drives RViz (rviz_screen) carries RVIZ."""
    for path in ALL_FILES:
        here = os.path.dirname(path)
        scripts = [os.path.join(here, name) for name in
                   re.findall(r'<test [^>]*type="([^"]+\.py)"', _text(path))]
        drives_rviz = any('rviz_screen' in _text(script) for script in scripts)
        assert drives_rviz == (RVIZ in _text(path)), path
