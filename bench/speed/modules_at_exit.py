#!/usr/bin/env python3
"""Run a Python script as __main__, then write the rbx1_nav modules it had
loaded when it ended (bench/bench.py's cpu section).

    modules_at_exit.py OUT.json SCRIPT [ARGS...]

OUT.json: [[module file, lines], ...] of every ``rbx1_nav`` module in
sys.modules at exit, written by atexit however the script ends (SystemExit
too, and rbx1_nav.common.node_ros.exit_node, which runs atexit's functions
before its os._exit). The script sees sys.argv as if run itself (rospy reads
its remappings there).
"""
import atexit
import json
import os
import runpy
import sys


def rbx1_nav_modules():
    """[(file, lines)] of the rbx1_nav modules loaded, by file name. The
    package's own __init__ stands for itself, not the one catkin generates
    in a devel space to run it."""
    found = []
    for name, module in list(sys.modules.items()):
        path = getattr(module, '__file__', None)
        if name.split('.')[0] != 'rbx1_nav' or not path:
            continue
        if name == 'rbx1_nav':
            path = next((init for init in (os.path.join(folder, '__init__.py')
                                           for folder in module.__path__)
                         if init != module.__file__ and os.path.isfile(init)), path)
        with open(path, 'rb') as f:
            found.append((path, f.read().count(b'\n')))
    return sorted(found)


def main():
    out, script = sys.argv[1], sys.argv[2]
    sys.argv = sys.argv[2:]

    def write():
        with open(out, 'w') as f:
            json.dump(rbx1_nav_modules(), f)
    atexit.register(write)  # a node's exit_node runs atexit's functions, then os._exit
    runpy.run_path(script, run_name='__main__')


if __name__ == '__main__':
    main()
