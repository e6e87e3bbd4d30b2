"""Every command the README shows is installed by `make demo`.

The commands are the first word of each line of the README's ``bash``
blocks, and the ``ros*``/``rviz`` commands quoted inline (e.g. a
``rosservice call`` in the text). Run with the workspace sourced (make
test does), each must be on PATH; the shell's own words and what the
Makefile itself runs are left out. The Noetic block is for another
machine and is left out too. The README's manual ``apt-get install``
line must name every package the Makefile installs.
"""
import os
import re
import shutil

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SHELL_WORDS = {'cd', 'source', 'mkdir', 'mv', 'sudo', 'git', 'make', 'python3'}


def readme():
    with open(os.path.join(ROOT, 'README.md')) as f:
        return f.read()


def shown_commands(text):
    """{command: first line showing it} from bash blocks and inline code."""
    found = {}
    blocks = re.findall(r'```bash\n(.*?)```', text, re.S)
    for block in blocks:
        if 'rosdep install' in block:  # the Noetic set-up, another machine
            continue
        for line in block.replace('\\\n', ' ').splitlines():
            line = line.split('#')[0].strip()
            for part in re.split(r'&&|\|', line):
                words = part.split()
                if words:
                    found.setdefault(words[0], line)
    for span in re.findall(r'`((?:ros[a-z]*|rviz) [^`]*)`', text):
        found.setdefault(span.split()[0], span)
    return found


def test_every_command_the_readme_shows_is_installed():
    commands = shown_commands(readme())
    assert {'roslaunch', 'rosrun', 'rviz', 'rostest', 'rosservice'} <= set(commands)
    missing = {c: line for c, line in commands.items()
               if c not in SHELL_WORDS and shutil.which(c) is None}
    assert not missing, 'the README shows these, make demo does not install them: %s' % missing


def test_the_readme_apt_line_names_every_package_the_makefile_installs():
    with open(os.path.join(ROOT, 'Makefile')) as f:
        makefile = f.read()
    wanted = set(re.search(r'DEB_PACKAGES := (.*?)\n[A-Z]', makefile, re.S)
                 .group(1).replace('\\', ' ').split())
    apt = set(re.search(r'sudo apt-get install (.*?)\n[a-z]', readme(), re.S)
              .group(1).replace('\\', ' ').split())
    assert 'python3-rosservice' in wanted
    assert wanted == apt, 'Makefile only: %s; README only: %s' % (
        sorted(wanted - apt), sorted(apt - wanted))
