"""The RViz views fit a laptop screen and close without a prompt; every
launch file argument is documented and none is required (checked through
``roslaunch --ros-args``, which calls an argument without a default, or with
an empty one, required)."""
import glob
import os
import shutil
import subprocess

import pytest
import yaml

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
RVIZ = sorted(glob.glob(os.path.join(ROOT, 'rviz', '*.rviz')))
LAUNCH = sorted(glob.glob(os.path.join(ROOT, 'launch', '*.launch')))
SCREEN = (1280, 800)  # a common laptop screen


@pytest.mark.parametrize('path', RVIZ, ids=[os.path.basename(p) for p in RVIZ])
def test_rviz_window_fits_the_screen_and_closes_without_a_prompt(path):
    with open(path) as f:
        config = yaml.safe_load(f)
    window = config['Window Geometry']
    assert window['X'] + window['Width'] <= SCREEN[0]
    assert window['Y'] + window['Height'] <= SCREEN[1]
    assert config['Preferences']['PromptSaveOnExit'] is False


@pytest.mark.parametrize('path', LAUNCH, ids=[os.path.basename(p) for p in LAUNCH])
def test_launch_arguments_are_documented_and_optional(path):
    if not shutil.which('roslaunch') or 'ROS_PACKAGE_PATH' not in os.environ:
        pytest.skip('needs a sourced ROS workspace (make test sources one)')
    proc = subprocess.run(['roslaunch', '--ros-args', path],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          universal_newlines=True, timeout=60)
    assert proc.returncode == 0, proc.stdout
    assert 'Required Arguments' not in proc.stdout, proc.stdout
    assert 'undocumented' not in proc.stdout, proc.stdout
