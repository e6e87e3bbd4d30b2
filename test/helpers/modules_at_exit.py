#!/usr/bin/env python3
"""Run a node script as rosrun would, and at its exit write the package's
modules it had loaded to the file $RBX1_NAV_MODULES_OUT, as JSON:
[[module name, file, lines], ...] (lines as `wc -l` counts them).

    modules_at_exit.py NODE_SCRIPT [ARGS...]
"""
import atexit
import json
import os
import runpy
import sys


def _dump():
    rows = []
    for name, module in sorted(sys.modules.items()):
        path = getattr(module, '__file__', None)
        if (name == 'rbx1_nav' or name.startswith('rbx1_nav.')) and path:
            with open(path, 'rb') as f:
                rows.append([name, path, f.read().count(b'\n')])
    with open(os.environ['RBX1_NAV_MODULES_OUT'], 'w') as f:
        json.dump(rows, f)


if __name__ == '__main__':
    script = sys.argv[1]
    sys.argv = sys.argv[1:]
    sys.path[0] = os.path.dirname(os.path.abspath(script))
    atexit.register(_dump)
    runpy.run_path(script, run_name='__main__')
