"""The README's node table lists exactly the parameters each node reads.

Each node declares every private parameter it reads (``PARAMS``, a tuple of
rbx1_nav.common.params.Param, read through rbx1_nav.common.node_ros.start_node) and
lists them for ``--help``, so that list is the truth; the README row of the
node must name each of them in backticks, and no other. "and the runner's"
in a row stands for the runner's row, "`NODE.py`'s" for that node's row.
"""
import glob
import os
import re
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
NODES = sorted(p for p in glob.glob(os.path.join(ROOT, 'nodes', '*.py'))
               # plot_course.py: argparse --help; end_launch_on_success.py: a
               # launch-prefix, unless_running.py: another node's wrapper,
               # launch_status.py: runs roslaunch; not nodes
               if not p.endswith(('plot_course.py', 'end_launch_on_success.py',
                                  'unless_running.py', 'launch_status.py')))


def readme_rows():
    """{first cell: set of backticked names in the last cell} of the table."""
    rows, others = {}, {}
    with open(os.path.join(ROOT, 'README.md')) as f:
        for line in f:
            cells = [c.strip() for c in line.strip().strip('|').split('|')]
            if len(cells) == 4 and cells[0].startswith('`') or \
                    cells[0].startswith('the runner'):
                names = set(re.findall(r'`([a-z][a-z0-9_]*)`', cells[-1]))
                if "the runner's" in cells[-1]:
                    names.add("the runner's")
                rows[cells[0].strip('`')] = names
                # "and `fake_turtlebot.py`'s": every parameter of that row
                others[cells[0].strip('`')] = re.findall(r"`([a-z_]+\.py)`'s",
                                                         cells[-1])
    runner = rows.get("the runner's (every node above)", set())
    for names in rows.values():
        if "the runner's" in names:
            names.discard("the runner's")
            names |= runner
    for node, names in rows.items():
        names |= set().union(*(rows.get(other, set()) for other in others[node]))
    return rows


def declared(path):
    """The parameters ``rosrun rbx1_nav NODE --help`` lists."""
    proc = subprocess.run(['rosrun', 'rbx1_nav', os.path.basename(path),
                           '--help'], stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, universal_newlines=True,
                          timeout=60)
    assert proc.returncode == 0, proc.stdout
    header = 'Private parameters (rosrun: _name:=value; launch: <param>):'
    assert header in proc.stdout, '%s --help lists no parameters' % path
    table = proc.stdout.split(header, 1)[1]
    return set(re.findall(r'^  ~([a-z][a-z0-9_]*) ', table, re.M))


@pytest.mark.parametrize('path', NODES, ids=[os.path.basename(p) for p in NODES])
def test_readme_row_names_every_parameter_and_no_other(path):
    node = os.path.basename(path)
    rows = readme_rows()
    assert node in rows, 'README.md has no node-table row for %s' % node
    code, readme = declared(path), rows[node]
    assert not code - readme, 'read by %s, missing from README.md: %s' % (
        node, sorted(code - readme))
    assert not readme - code, 'in README.md, read by no %s: %s' % (
        node, sorted(readme - code))
