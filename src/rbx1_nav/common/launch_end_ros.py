"""The master side of nodes/end_launch_on_success.py (the rest, rospy-free:
rbx1_nav.common.launch_end): forget a launched node's private parameters
once it has ended.

roslaunch sets a node's private parameters at start (``clear_params``
clears the old ones first) and leaves them on the master when it ends; a
later ``rosrun`` of the same node would take them as its own (a scaled
~start_delay, precise:=true) and warn about leftovers. The wrapper removes
them when its node ends, under roslaunch only (rostest's test scripts may
still read them).
"""
import xmlrpc.client

import rosgraph

from rbx1_nav.common.master_watch import proxy

__all__ = ['forget_params']

CALLER = '/rbx1_nav_end_launch'


def forget_params(name):
    """Remove the parameters under the global name ``name`` (a node's
    private namespace) from the master; quietly nothing if it has none, or
    the master is gone (it may end with the launch)."""
    try:
        proxy(rosgraph.get_master_uri()).deleteParam(CALLER, name)
    except (OSError, xmlrpc.client.Error):
        pass
