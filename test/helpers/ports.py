"""A free TCP port for a test's own roscore (imported, not a node)."""
import os
import socket

import pytest


def free_port(ports):
    """The first port of ``ports`` nothing listens on; the test fails, naming
    them, when every one is taken (a skip would pass in CI unseen). Each test file has a range of its own, and
    each pytest-xdist worker takes every n-th port of it (n workers), so
    tests running side by side never race for one port: two tests of one
    file in two workers both found the first port free before either
    roscore had bound it, and one test met the other's master."""
    worker = os.environ.get('PYTEST_XDIST_WORKER', 'gw0')
    count = int(os.environ.get('PYTEST_XDIST_WORKER_COUNT', '1'))
    mine = ports[int(worker[len('gw'):]) % count::count]
    for port in mine:
        with socket.socket() as s:
            try:
                s.bind(('', port))
            except OSError:
                continue
            return port
    pytest.fail('every port of %s is taken (a roscore left over? `pgrep -af rosmaster`); this '
                'test needs one for its own master' % list(mine))
