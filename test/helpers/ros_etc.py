"""An /etc/ros for the suite whose roscore.xml starts no process (imported,
not a node).

Every roslaunch, rostest's and roscore's included, first loads
``$ROS_ETC_DIR/roscore.xml``, whose two ``<param command="rosversion ...">``
run rosversion twice: about 0.1 CPU s a launch, and the suite makes some
95 launches. :func:`use_answered_etc` runs each such command once and
points ROS_ETC_DIR at a copy of the directory whose roscore.xml reads what
the command printed from a file (``textfile``, which keeps the output as
it is, trailing newline included, as ``command`` does): the same
parameters, with the rest of the directory (python_logging.conf, ...)
linked from the original.
"""
import atexit
import os
import shlex
import shutil
import subprocess
import tempfile
import xml.etree.ElementTree as ElementTree

import rospkg


def command_params(tree):
    """The <param> elements of a parsed roscore.xml that run a command."""
    return [param for param in tree.iter('param') if 'command' in param.attrib]


def answered_etc(source, target):
    """Fill ``target`` with ``source``'s entries, roscore.xml's commands
    answered (each run once, its output in a file the param reads)."""
    tree = ElementTree.parse(os.path.join(source, 'roscore.xml'))
    for number, param in enumerate(command_params(tree)):
        output = subprocess.run(shlex.split(param.attrib.pop('command')),
                                stdout=subprocess.PIPE, check=True).stdout
        answer = os.path.join(target, 'roscore_param_%d.txt' % number)
        with open(answer, 'wb') as f:
            f.write(output)
        param.set('textfile', answer)
    tree.write(os.path.join(target, 'roscore.xml'))
    for name in os.listdir(source):
        if name != 'roscore.xml':
            os.symlink(os.path.join(source, name), os.path.join(target, name))


def use_answered_etc():
    """Point ROS_ETC_DIR, for this process and what it starts, at an
    answered copy of the current one (removed at exit); nothing to do when
    its roscore.xml runs no command (a copy made by a parent process), and
    ROS_ETC_DIR left as it was when a command fails (roslaunch will say
    why)."""
    source = rospkg.get_etc_ros_dir()
    try:
        if not command_params(ElementTree.parse(os.path.join(source, 'roscore.xml'))):
            return
    except (OSError, ElementTree.ParseError):
        return  # roslaunch falls back to its own copy: leave it be
    target = tempfile.mkdtemp(prefix='rbx1_nav_etc_ros_')
    atexit.register(shutil.rmtree, target, True)
    try:
        answered_etc(source, target)
    except (OSError, subprocess.CalledProcessError):
        return
    os.environ['ROS_ETC_DIR'] = target
