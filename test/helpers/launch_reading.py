"""What ``roslaunch --dump-params``, ``--nodes`` and ``--args`` print for
one of the package's launch files, read with roslaunch's own loader in
the test's process: a roslaunch process per question cost about 0.4 CPU s.
Each function takes the launch file's name in launch/ and its ``name:=value``
arguments."""
import os

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))


def _files(launch, args):
    return [(os.path.join(ROOT, 'launch', launch), list(args))]


def _config(launch, args):
    import roslaunch.config
    return roslaunch.config.load_config_default(_files(launch, args), None, verbose=False,
                                                assign_machines=False)


def params(launch, *args):
    """{name: value} of every parameter the launch sets (--dump-params)."""
    return {name: param.value for name, param in _config(launch, args).params.items()}


def nodes(launch, *args):
    """The resolved name of every node the launch starts (--nodes)."""
    import roslaunch.node_args
    return roslaunch.node_args.get_node_list(_config(launch, args))


def node_command(node, launch, *args):
    """The command line the launch runs ``node`` with, environment first
    (--args)."""
    import roslaunch.node_args
    return ' '.join(roslaunch.node_args.get_node_args(node, _files(launch, args)))
