"""The master side of nodes/end_launch_on_success.py (the rest, rospy-free:
rbx1_nav.common.launch_end): forget a launched node's private parameters
once it has ended, and a launch's simulated time once its clock has
(:func:`end_sim_time`, sim_clock's too).

roslaunch sets a node's private parameters at start (``clear_params``
clears the old ones first) and leaves them on the master when it ends; a
later ``rosrun`` of the same node would take them as its own (a scaled
~start_delay, precise:=true) and warn about leftovers. The wrapper removes
them when its node ends, under roslaunch only (rostest's test scripts may
still read them).
"""
import xmlrpc.client

import rosgraph

from rbx1_nav.common.launch_end import sim_time_to_clear
from rbx1_nav.common.master_watch import proxy

__all__ = ['forget_params', 'end_sim_time']

CALLER = '/rbx1_nav_end_launch'


def forget_params(name):
    """Remove the parameters under the global name ``name`` (a node's
    private namespace) from the master; quietly nothing if it has none, or
    the master is gone (it may end with the launch)."""
    try:
        proxy(rosgraph.get_master_uri()).deleteParam(CALLER, name)
    except (OSError, xmlrpc.client.Error):
        pass


def _answers(master, name):
    """True if node ``name``, registered with ``master``, answers (a killed
    node stays registered)."""
    try:
        code, _, uri = master.lookupNode(CALLER, name)
        return code == 1 and proxy(uri).getPid(CALLER)[0] == 1
    except (OSError, xmlrpc.client.Error):
        return False


def end_sim_time(own=None):
    """As a launch's clock ends (``own``: its node name, if it is still
    registered): remove /use_sim_time and /lockstep, unless another running
    node publishes /clock (launch_end.sim_time_to_clear); quietly nothing
    if the master is gone (it may end with the launch)."""
    try:
        master = proxy(rosgraph.get_master_uri())
        code, _, state = master.getSystemState(CALLER)
        clocks = dict(state[0]).get('/clock', []) if code == 1 else []
        others = [name for name in clocks if name != own and _answers(master, name)]
        for name in sim_time_to_clear(True, others):
            master.deleteParam(CALLER, name)
    except (OSError, xmlrpc.client.Error):
        pass
