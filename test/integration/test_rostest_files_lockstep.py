"""The rostests under lockstep (see test_rostest_files.py).

Those at full speed keep a core busy; they run one after another in one
worker (an xdist group), so the other worker takes the tests that mostly
wait on wall time (the two-host faults, the lockstep ones at 1x and 5x).
"""
import os

import pytest

from test_rostest_files import LOCKSTEP_FILES, TEST_DIR, at_full_speed, run_rostest

PARAMS = [pytest.param(f, id=os.path.relpath(f, TEST_DIR),
                       marks=[pytest.mark.xdist_group('full_speed')] if at_full_speed(f) else [])
          for f in LOCKSTEP_FILES]


@pytest.mark.parametrize('test_file', PARAMS)
def test_rostest(test_file):
    run_rostest(test_file)
