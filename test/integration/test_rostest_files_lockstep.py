"""The rostests under lockstep at full speed (see test_rostest_files.py)."""
import os

import pytest

from test_rostest_files import LOCKSTEP_FILES, run_rostest


@pytest.mark.parametrize('test_file', LOCKSTEP_FILES,
                         ids=[os.path.basename(f) for f in LOCKSTEP_FILES])
def test_rostest(test_file):
    run_rostest(test_file)
