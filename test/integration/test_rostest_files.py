"""Run every test/*.test file through rostest, one pytest case each.

This lets `make test` report unit and integration results in one pytest
summary. `catkin_make run_tests` runs the same files through add_rostest().
"""
import glob
import os
import subprocess

import pytest

TEST_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TEST_FILES = sorted(glob.glob(os.path.join(TEST_DIR, '*.test')))


@pytest.mark.parametrize('test_file', TEST_FILES,
                         ids=[os.path.basename(f) for f in TEST_FILES])
def test_rostest(test_file):
    # Not --text: with it rostest exits 0 even when a test fails.
    proc = subprocess.run(['rostest', test_file],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          universal_newlines=True, timeout=600)
    assert proc.returncode == 0, '%s failed:\n%s' % (
        os.path.basename(test_file), proc.stdout[-6000:])
