"""Every command README.md and the pages of docs/ show works as typed.

The commands are the lines of the pages' ``bash`` blocks and the
``ros*``/``rviz`` commands quoted inline (e.g. a ``rosservice call`` in the
text). Run with the workspace sourced (make test does):

- the first word of each must be on PATH; the shell's own words and what
  the Makefile itself runs are left out, and so is the Noetic block (it
  holds ``rosdep install``), which is for another machine;
- ``roslaunch rbx1_nav X.launch name:=value``: the launch file exists and
  each ``name`` is one of its ``<arg>`` (rbx1_bringup's lines: of
  ``.rbx1_bringup/launch``), and so for the launch ``launch_status.py``
  starts;
- ``rosrun rbx1_nav NODE _name:=value topic:=other``: the node exists in
  nodes/, each ``_name`` is one of its declared parameters (``PARAMS``)
  and each remap a legal name;
- ``rostest rbx1_nav X.test``: the test file exists.

The manual ``apt-get install`` line (on the install page) must name every
package the Makefile installs. No master is needed: the launch files are
read with xml.etree, a node's parameters from its file.
"""
import glob
import os
import sys
import re
import shlex
import shutil
import xml.etree.ElementTree as ET

import pytest
import yaml

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'helpers'))
import parameters_page  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SHELL_WORDS = {'cd', 'export', 'source', 'mkdir', 'mv', 'sudo', 'git', 'make', 'python3'}
PAGES = ['README.md'] + sorted(os.path.relpath(p, ROOT) for p in
                               glob.glob(os.path.join(ROOT, 'docs', '*.md')))
LAUNCH_DIRS = {'rbx1_nav': os.path.join(ROOT, 'launch'),
               'rbx1_bringup': os.path.join(ROOT, '.rbx1_bringup', 'launch')}
#: rospy's special arguments a rosrun line may give a node.
SPECIAL = {'__ns', '__name', '__log', '__ip', '__hostname', '__master'}
#: A graph name a remap may name on either side.
NAME = re.compile(r'^[/~]?[A-Za-z][A-Za-z0-9_/]*$')
PLACEHOLDER = re.compile(r'^[A-Z]+(\.[a-z]+)?$')


def read(page):
    with open(os.path.join(ROOT, page)) as f:
        return f.read()


def command_lines(text):
    """Every command line of ``text``: each part (split at ``&&`` and
    ``|``) of each line of its bash blocks, comments cut, and each inline
    ``ros*``/``rviz`` command, whitespace made single."""
    lines = []
    for block in re.findall(r'```bash\n(.*?)```', text, re.S):
        if 'rosdep install' in block:  # the Noetic set-up, another machine
            continue
        for line in block.replace('\\\n', ' ').splitlines():
            line = line.split('#')[0].strip()
            lines += [part.strip() for part in re.split(r'&&|\|', line) if part.strip()]
    for span in re.findall(r'`((?:ros[a-z]*|rviz) [^`]*)`', text):
        lines.append(' '.join(span.split()))
    return lines


def words(line):
    try:
        return shlex.split(line)
    except ValueError:  # an unbalanced quote in prose
        return line.split()


def shown_commands(text):
    """{command: first line showing it}."""
    found = {}
    for line in command_lines(text):
        found.setdefault(line.split()[0], line)
    return found


def launch_args(path):
    """The ``<arg>`` names a command line can set: those not inside an
    ``<include>`` (which pass values to the included file)."""
    names = set()

    def walk(element):
        for child in element:
            if child.tag == 'arg':
                names.add(child.get('name'))
            elif child.tag != 'include':
                walk(child)
    walk(ET.parse(path).getroot())
    return names


GENERATOR = parameters_page.load()
_PARAMS = {}


def node_params(node):
    """The private parameters ``node`` (a file in nodes/) declares, by
    name; none for the helpers, which take none."""
    if node not in _PARAMS:
        path = os.path.join(ROOT, 'nodes', node)
        _PARAMS[node] = ({} if node in GENERATOR.NOT_NODES else
                         {spec.name: spec for spec in GENERATOR.load(path).PARAMS})
    return _PARAMS[node]


def value_problem(spec, text):
    """Why the node would refuse ``_name:=text`` (rospy reads the text as
    YAML, as here), or None; a value with '...' in it is a placeholder."""
    if '...' in text:
        return None
    try:
        spec.check('~' + spec.name, yaml.safe_load(text), **spec.options)
    except ValueError as err:
        return str(err)
    return None


def launch_problems(package, launch, args):
    """What is wrong with ``roslaunch package launch args...``."""
    folder = LAUNCH_DIRS.get(package)
    if folder is None:  # another package's launch file (turtlebot_bringup)
        return []
    path = os.path.join(folder, launch)
    if not os.path.isfile(path):
        return ['%s has no launch file %s' % (package, launch)]
    known = launch_args(path)
    return ['%s is not an <arg> of %s' % (name, launch)
            for name in (arg.split(':=', 1)[0] for arg in args if ':=' in arg)
            if name not in known]


def problems(line):
    """What is wrong with one command line (empty when nothing). A word in
    capitals (NODE.py, X.launch) is a placeholder."""
    w = words(line)
    if any(PLACEHOLDER.match(word) for word in w[1:3]):
        return []
    if len(w) >= 3 and w[0] == 'roslaunch' and w[2].endswith('.launch'):
        return launch_problems(w[1], w[2], w[3:])
    if len(w) >= 3 and w[0] == 'rostest' and w[1] == 'rbx1_nav':
        found = [p for d in ('rostest', 'faults')
                 for p in [os.path.join(ROOT, 'test', d, w[2])] if os.path.isfile(p)]
        return [] if found else ['no test file %s in test/rostest or test/faults' % w[2]]
    if len(w) < 3 or w[0] != 'rosrun' or w[1] != 'rbx1_nav':
        return []
    node = w[2]
    if not os.path.isfile(os.path.join(ROOT, 'nodes', node)):
        return ['no node %s in nodes/' % node]
    if node == 'launch_status.py' and len(w) >= 5:
        return launch_problems(w[3], w[4], w[5:])
    found = []
    for arg in w[3:]:
        name, sep, _ = arg.partition(':=')
        if not sep:
            continue
        if name.startswith('__'):
            if name not in SPECIAL:
                found.append('%s is not a rospy special argument' % name)
        elif name.startswith('_'):
            spec = node_params(node).get(name[1:])
            if spec is None:
                found.append('%s declares no parameter ~%s' % (node, name[1:]))
            elif value_problem(spec, arg.partition(':=')[2]):
                found.append(value_problem(spec, arg.partition(':=')[2]))
        elif not NAME.match(name):
            found.append('%s is not a name to remap' % name)
    return found


def test_every_command_the_pages_show_is_installed():
    commands = {}
    for page in PAGES:
        for command, line in shown_commands(read(page)).items():
            commands.setdefault(command, '%s: %s' % (page, line))
    assert {'roslaunch', 'rosrun', 'rviz', 'rostest', 'rosservice'} <= set(commands)
    missing = {c: line for c, line in commands.items()
               if c not in SHELL_WORDS and shutil.which(c) is None}
    assert not missing, 'the docs show these, make demo does not install them: %s' % missing


@pytest.mark.parametrize('page', PAGES)
def test_every_launch_arg_node_parameter_and_test_file_exists(page):
    lines = command_lines(read(page))
    found = ['%s\n    %s' % (line, '; '.join(problems(line)))
             for line in lines if problems(line)]
    assert not found, '%s shows commands that do not work as typed:\n%s' % (
        page, '\n'.join(found))


def test_the_checks_catch_a_wrong_arg_parameter_node_and_test_file():
    assert problems('roslaunch rbx1_nav nav_square.launch precise:=true sim:=true') == []
    assert problems('roslaunch rbx1_nav nav_square.launch precsie:=true') == [
        'precsie is not an <arg> of nav_square.launch']
    assert problems('roslaunch rbx1_nav no_such.launch') == [
        'rbx1_nav has no launch file no_such.launch']
    assert problems('roslaunch rbx1_bringup odom_ekf.launch') == []
    assert problems('rosrun rbx1_nav nav_square.py _precise:=true cmd_vel:=a/b __ns:=r1') == []
    assert problems('rosrun rbx1_nav nav_square.py _gaol_distance:=1') == [
        'nav_square.py declares no parameter ~gaol_distance']
    assert problems('rosrun rbx1_nav odom_out_and_back.py _goal_angle:=180 _precise:=maybe') == [
        '~goal_angle must be >= -12.5664 and <= 12.5664, got 180',
        "~precise must be true or false, got 'maybe'"]
    assert problems('rosrun rbx1_nav plot_course.py course.bag -o course.png') == []
    assert problems('rosrun rbx1_nav no_such.py') == ['no node no_such.py in nodes/']
    assert problems('rosrun rbx1_nav launch_status.py rbx1_nav nav_square.launch sim:=1 x:=2') == [
        'x is not an <arg> of nav_square.launch']
    assert problems('rostest rbx1_nav courses.test') == []
    assert problems('rostest rbx1_nav out_and_back_no_tf.test') == []
    assert problems('rostest rbx1_nav no_such.test') == [
        'no test file no_such.test in test/rostest or test/faults']
    assert problems('rosrun rbx1_nav NODE.py --help') == []


def test_the_apt_line_names_every_package_the_makefile_installs():
    with open(os.path.join(ROOT, 'Makefile')) as f:
        makefile = f.read()
    wanted = set(re.search(r'DEB_PACKAGES := (.*?)\n[A-Z]', makefile, re.S)
                 .group(1).replace('\\', ' ').split())
    lines = [(page, match) for page in PAGES for match in
             re.findall(r'sudo apt-get install (.*?)\n[a-z]', read(page), re.S)]
    assert len(lines) == 1, 'one page holds the manual apt-get line: %s' % [
        page for page, _ in lines]
    page, match = lines[0]
    apt = set(match.replace('\\', ' ').split())
    assert 'python3-rosservice' in wanted
    assert wanted == apt, 'Makefile only: %s; %s only: %s' % (
        sorted(wanted - apt), page, sorted(apt - wanted))
