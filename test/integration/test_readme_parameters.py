"""docs/parameters.md is what the nodes' declarations give, and so is --help.

Each node declares every private parameter it reads (``PARAMS``, a tuple of
rbx1_nav.common.params.Param, read through rbx1_nav.common.node_ros.start_node).
``docs/make_parameters.py`` (``make docs``) writes the page from those
declarations and the nodes' docstrings, and ``--help`` prints the same
declarations: the page must be what the generator writes now, and each
node's ``--help`` must list the parameters of its ``PARAMS``, so neither
can drift from the code.
"""
import os
import sys
import re
import subprocess

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'helpers'))
import parameters_page  # noqa: E402
from rosrun import rosrun  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


GENERATOR = parameters_page.load()
NODES = GENERATOR.node_files()


def test_the_page_is_what_make_docs_writes():
    with open(GENERATOR.PAGE) as f:
        page = f.read()
    assert page == GENERATOR.render(), (
        'docs/parameters.md is stale: run make docs')


def test_every_node_file_is_on_the_page_but_the_helpers():
    names = {os.path.basename(p) for p in NODES}
    every = set(os.listdir(os.path.join(ROOT, 'nodes')))
    assert names == {n for n in every if n.endswith('.py')} - set(GENERATOR.NOT_NODES)
    assert set(GENERATOR.NOT_NODES) <= every
    with open(GENERATOR.PAGE) as f:
        page = f.read()
    for name in names:
        assert '\n## `%s`\n' % name in page, name


def listed(path):
    """The parameters ``rosrun rbx1_nav NODE --help`` lists."""
    proc = subprocess.run(rosrun('rbx1_nav', os.path.basename(path), '--help'),
                          stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, universal_newlines=True,
                          timeout=60)
    assert proc.returncode == 0, proc.stdout
    header = 'Private parameters (rosrun: _name:=value; launch: <param>):'
    assert header in proc.stdout, '%s --help lists no parameters' % path
    table = proc.stdout.split(header, 1)[1]
    return re.findall(r'^  ~([a-z][a-z0-9_]*) ', table, re.M)


@pytest.mark.parametrize('path', NODES, ids=[os.path.basename(p) for p in NODES])
def test_help_lists_the_parameters_of_params(path):
    declared = [spec.name for spec in GENERATOR.load(path).PARAMS]
    assert listed(path) == declared, (
        '%s --help and its PARAMS differ' % os.path.basename(path))
