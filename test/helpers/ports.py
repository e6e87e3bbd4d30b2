"""A free TCP port for a test's own roscore (imported, not a node)."""
import socket

import pytest


def free_port(ports):
    """The first port of ``ports`` nothing listens on; the test is skipped
    when every one is taken. Each test file has a range of its own, so
    tests running side by side do not race for one port."""
    for port in ports:
        with socket.socket() as s:
            try:
                s.bind(('', port))
            except OSError:
                continue
            return port
    pytest.skip('no free port in %d-%d' % (ports[0], ports[-1]))
