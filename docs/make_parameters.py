"""Write docs/parameters.md from the nodes' own declarations.

Each node file in nodes/ says what it does (its docstring) and declares its
private parameters (``PARAMS``, rbx1_nav.common.params.Param): ``--help``
prints them (params_help.usage), this page shows them as Markdown
(params_help.markdown), so the two cannot drift. A node file is imported by
path; its ``if __name__ == '__main__'`` guard keeps it from running.

    make docs                                 # the workspace built
    python3 docs/make_parameters.py [--check] # the workspace sourced

test/integration/test_readme_parameters.py fails on a stale page.
"""
import argparse
import glob
import importlib.util
import os
import sys

from rbx1_nav.common import params_help

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PAGE = os.path.join(ROOT, 'docs', 'parameters.md')

#: Files in nodes/ that are not nodes with parameters: plot_course.py takes
#: argparse options; end_launch_on_success.py is a launch-prefix,
#: unless_running.py another node's wrapper, launch_status.py runs roslaunch.
NOT_NODES = ('plot_course.py', 'end_launch_on_success.py', 'unless_running.py',
             'launch_status.py')

#: The order of the page: the courses, the calibrations, driving by hand,
#: the simulators and their clock, the filters. Nodes not named here follow.
ORDER = ('odom_out_and_back.py', 'timed_out_and_back.py', 'nav_square.py',
         'calibrate_linear.py', 'calibrate_angular.py', 'umbmark.py',
         'teleop_keyboard.py', 'fake_turtlebot.py', 'fake_fleet.py',
         'sim_clock.py', 'lockstep_play.py', 'pose_ekf.py', 'odom_ekf.py')

HEADER = """\
# Nodes and their parameters

Every node of the package: what it does, its topics and its private
parameters with their defaults, units and bounds. This page is generated
from the declarations that also give `rosrun rbx1_nav NODE.py --help`
(`make docs` writes it from `docs/make_parameters.py`; do not edit it by
hand: `test/integration/test_readme_parameters.py` fails on a stale page).

Every parameter is private: `_name:=value` after `rosrun`, `<param>` in a
launch file. Every node logs the values it uses at start-up, prints them
with their defaults for `rosrun rbx1_nav NODE.py --help` (no master
needed), and waits, saying so, while there is no ROS master. It refuses to
start on a private parameter it does not know that its command line or
launch file gives it, naming the nearest one it does (`_gaol_distance:=0.5`:
did you mean `~goal_distance`?; exit 1: a typo must not run the default),
and only warns of one left on the parameter server by an earlier run. A
value given as `_name:=value` stays on the parameter server for later runs
once the node has started; a node that refuses to start (a typo, a bad
value) leaves the parameter server as it found it, and the error for a bad
value held there says how to clear it (`rosparam delete
/nav_square/linear_speed`). Frame names given with a leading `/` are
accepted and the slash dropped (tf2 rejects it). The launch files take the
same settings as arguments (`roslaunch rbx1_nav nav_square.launch
precise:=true`; `roslaunch --ros-args` lists them).

**The runner's parameters.** The motion nodes (`odom_out_and_back.py`,
`timed_out_and_back.py`, `nav_square.py`, the calibrations, `umbmark.py`)
end with the runner's (`rbx1_nav.motion.runner.runner_ros`, from `rate` on), and
all of them also hear `odom`, only its velocity: the summary counts the
spells the robot stood still while commanded. In more detail: `tf_wait`
counts wall seconds, for `/clock` under simulated time, the first
transform and a `cmd_vel` subscriber. `tf_timeout` is the transform's
staleness, by its stamp or since one last arrived, whichever is longer:
the robot is held. `link_grace` is how much longer to wait for it before
giving up (a Wi-Fi dropout). `max_tf_age` warns, at most every 10 s, when
the transform steered by is older (a slow link). `settle_time`: after the
last step the robot is commanded zero until its host has every command
sent before (by TCP's acknowledgements) and odometry has then stood still
this long, longer than the robot's `cmd_vel` watchdog; the summary gives
that pose. `settle_timeout` is odometry's time: then it says the robot did
not settle (a stale transform meanwhile is held as in the course). How the
motion nodes are built (a list of steps, one runner) is in
[design.md](design.md#the-motion-nodes).

Not here: `plot_course.py BAG` reads a bag with odom (and ground_truth,
the fused pose) and writes a PNG; it takes options, not parameters (`-o`
output path, `--odom-topic`, `--truth-topic`, `--fused-topic`; see
`--help`). `launch_status.py`, `end_launch_on_success.py` and
`unless_running.py` are helpers of the launch files
([courses.md](courses.md#launch_statuspy-a-launchs-exit-status)).
"""


def node_files():
    """Every node file with parameters, in the page's order."""
    found = {os.path.basename(p): p for p in glob.glob(os.path.join(ROOT, 'nodes', '*.py'))
             if not p.endswith(NOT_NODES)}
    return ([found[name] for name in ORDER if name in found]
            + [found[name] for name in sorted(found) if name not in ORDER])


def load(path):
    """The node file at ``path`` as a module (its main guard keeps it idle)."""
    name = '_rbx1_nav_node_' + os.path.basename(path)[:-3]
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def render():
    """The text of docs/parameters.md."""
    sections = [HEADER]
    for path in node_files():
        node = load(path)
        sections.append(params_help.markdown(os.path.basename(path), node.__doc__,
                                        node.PARAMS))
    return '\n'.join(sections)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--check', action='store_true',
                        help='exit 1 if the page is stale, writing nothing')
    args = parser.parse_args(argv)
    text = render()
    current = ''
    if os.path.exists(PAGE):
        with open(PAGE) as f:
            current = f.read()
    if args.check:
        if current != text:
            print('%s is stale: run make docs' % os.path.relpath(PAGE, ROOT))
            return 1
        return 0
    if current != text:
        with open(PAGE, 'w') as f:
            f.write(text)
    print('docs: wrote %s' % os.path.relpath(PAGE, ROOT))
    return 0


if __name__ == '__main__':
    sys.exit(main())
