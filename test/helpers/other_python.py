"""Another python3 first on PATH, as pyenv, conda or a venv puts one
(imported, not a node): a venv of this interpreter made without the
system's site-packages, so its python3 cannot import rospy, as theirs
cannot. ROS's command-line tools that start with ``#!/usr/bin/env python3``
(dynparam) then fail with "No module named ..."."""
import os
import subprocess
import sys


def path_with_other_python(folder):
    """PATH with a python3 that has no rospy first; ``folder``: a new
    directory for it."""
    subprocess.run([sys.executable, '-m', 'venv', '--without-pip', str(folder)], check=True)
    return os.path.join(str(folder), 'bin') + os.pathsep + os.environ['PATH']


def lacks_rospy(path):
    """True when the python3 first on ``path`` cannot import rospy (the
    stand-in is what the README's PATH line guards against)."""
    probe = subprocess.run(['python3', '-c', 'import rospy'], env=dict(os.environ, PATH=path),
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           universal_newlines=True)
    return probe.returncode != 0 and "No module named 'rospy'" in probe.stdout
