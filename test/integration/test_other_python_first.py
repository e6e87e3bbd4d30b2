"""The package's rostests run with ROS's Python whatever python3 comes
first on PATH.

A script a .test file starts (``<test type="X_test.py">``) is found by
roslaunch as catkin's devel-space relay (CMakeLists.txt installs them with
catkin_install_python), whose first line names the interpreter the
workspace was built with, not ``/usr/bin/env python3``: with pyenv's,
conda's or a venv's python3 first, that would have no rospy. Checked for
every script, and by typing ``rostest rbx1_nav turtlebot2_remap.test``
with a python3 without rospy first on PATH (test/helpers/other_python.py):
it passes (the script's own verdict: its two courses, judged by ground
truth). The README's PATH line, for ROS's own tools, is typed by
test_readme_rehearsal.py.
"""
import glob
import os
import re
import shutil
import subprocess
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(HERE, '..', 'helpers'))
from other_python import lacks_rospy, path_with_other_python  # noqa: E402

pytestmark = pytest.mark.skipif(
    not shutil.which('rostest') or 'ROS_PACKAGE_PATH' not in os.environ,
    reason='needs a sourced ROS workspace (make test sources one)')

TEST_FILES = sorted(glob.glob(os.path.join(ROOT, 'test', 'rostest', '*.test'))
                    + glob.glob(os.path.join(ROOT, 'test', 'faults', '*.test')))
#: Under lockstep (its verdict does not depend on load), two short courses.
ROSTEST = 'turtlebot2_remap.test'


def built_with():
    """PYTHON_EXECUTABLE of the workspace whose devel space is sourced."""
    for prefix in os.environ.get('CMAKE_PREFIX_PATH', '').split(':'):
        cache = os.path.join(prefix, '..', 'build', 'CMakeCache.txt')
        if prefix.endswith('/devel') and os.path.isfile(cache):
            with open(cache) as f:
                return re.search(r'^PYTHON_EXECUTABLE:\w+=(.*)$', f.read(), re.M).group(1)
    pytest.skip('not run from a sourced catkin devel space')


def test_every_rostest_script_starts_with_the_python_the_workspace_was_built_with():
    import rospkg
    from roslib.packages import find_node
    rospack = rospkg.RosPack()
    interpreter = built_with()
    scripts = sorted({script for path in TEST_FILES for script in re.findall(
        r'type="(\w+_test\.py)"', open(path).read())})
    assert len(scripts) > 20, scripts
    wrong = {}
    for script in scripts:
        found = find_node('rbx1_nav', script, rospack=rospack)[0]  # roslaunch runs the first
        with open(found) as f:
            first = f.readline().strip()
        if first != '#!' + interpreter:
            wrong[script] = '%s: %s' % (found, first)
    assert not wrong, 'roslaunch would start these with another interpreter than %s: %s' % (
        interpreter, wrong)


def test_a_rostest_passes_with_another_python3_first_on_path(tmp_path):
    path = path_with_other_python(tmp_path / 'venv')
    assert lacks_rospy(path)
    proc = subprocess.run(['rostest', 'rbx1_nav', ROSTEST],
                          env=dict(os.environ, PATH=path, ROS_LOG_DIR=str(tmp_path)),
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          universal_newlines=True, timeout=600)
    assert proc.returncode == 0, proc.stdout[-4000:]
    assert "No module named" not in proc.stdout, proc.stdout[-4000:]
