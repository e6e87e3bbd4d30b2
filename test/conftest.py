"""`make test` runs three pytest workers on two cores (see the Makefile).

The tests whose processes follow the wall clock (the free-running
rostests, the two-host fault suite: xdist groups in NORMAL_PRIORITY) run
at normal priority; every other test, and what it starts, at niceness
LOW_PRIORITY. Those others are unit tests, or graphs under lockstep that
end the same however slowly they run, so they take whatever CPU the
clock-bound tests leave and cannot make them fall behind.
"""
import importlib
import os
import sys

import pytest

# One BLAS thread in the tests and every process they start, as the nodes
# have: importing rbx1_nav sets OPENBLAS_NUM_THREADS and the like, and a
# test importing numpy first must not start the spinning threads either.
importlib.import_module('rbx1_nav')

# roscore.xml's parameters answered once for the whole run, not by two
# rosversion processes at every launch (test/helpers/ros_etc.py). The
# install-space launches read the system's own, and check that it gives
# the same (test/integration/test_install_space.py).
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), 'helpers'))
importlib.import_module('ros_etc').use_answered_etc()

NORMAL_PRIORITY = {'free_running', 'two_hosts'}
LOW_PRIORITY = 5


def _order(item):
    """Where ``item`` goes in the run: the long one-after-another groups
    first, then the graphs, then the unit tests, which are short and fill
    the gaps at the end. pytest-xdist hands out work in collection order,
    so a group collected last (the two-host suite, about two minutes of
    mostly waiting) would otherwise run alone at the end of the run."""
    if _group(item) in NORMAL_PRIORITY:
        return 0
    return 2 if os.sep + 'unit' + os.sep in str(item.fspath) else 1


def pytest_collection_modifyitems(items):
    items.sort(key=_order)  # stable: collection order within each part


def _group(item):
    marker = item.get_closest_marker('xdist_group')
    if marker is None:
        return None
    return marker.args[0] if marker.args else marker.kwargs.get('name')


#: The suite that makes two hosts, which needs root (test/faults/link.py).
TWO_HOSTS = os.path.join('test', 'faults', 'test_two_hosts.py')


def pytest_terminal_summary(terminalreporter):
    """One line near the end when the two-host fault suite was skipped (no
    root): pytest's last line counts its tests as skipped and make test
    exits 0, so say which did not run and why."""
    skipped = [report for report in terminalreporter.stats.get('skipped', [])
               if os.path.basename(report.nodeid.split('::')[0]) == os.path.basename(TWO_HOSTS)]
    if skipped:
        longrepr = skipped[0].longrepr
        why = longrepr[2] if isinstance(longrepr, tuple) else str(longrepr)
        why = why[len('Skipped: '):] if why.startswith('Skipped: ') else why
        terminalreporter.write_line('The two-host fault tests did not run (%d skipped, %s): %s' % (
            len(skipped), TWO_HOSTS, why), yellow=True)


@pytest.fixture(autouse=True)
def _priority(request):
    """Set this worker's niceness for the test (inherited by what it starts)."""
    nice = 0 if _group(request.node) in NORMAL_PRIORITY else LOW_PRIORITY
    try:
        os.setpriority(os.PRIO_PROCESS, 0, nice)
    except PermissionError:  # only root may lower it again: leave it
        pass
    yield
