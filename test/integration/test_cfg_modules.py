"""The book's dynamic_reconfigure configs import as the book's scripts do:
``from rbx1_nav.cfg import CalibrateLinearConfig``, from the devel space and
from the install space (``make install`` of the workspace that runs the
tests, imported in a clean environment with only the install space set up).
"""
import os
import subprocess

import pytest

IMPORT = ('import rbx1_nav, rbx1_nav.ros.runner; '
          'from rbx1_nav.cfg import CalibrateLinearConfig as L, '
          'CalibrateAngularConfig as A; '
          'print(rbx1_nav.__file__); print(sorted(L.defaults)); '
          'print(sorted(A.defaults))')
LINEAR_FIELDS = ['measured_distance', 'odom_linear_scale_correction', 'speed',
                 'start_test', 'test_distance', 'tolerance']
ANGULAR_FIELDS = ['measured_angle', 'odom_angular_scale_correction', 'speed',
                  'start_test', 'test_angle', 'tolerance']


def workspace():
    """The catkin workspace whose devel space the tests run in."""
    for prefix in os.environ.get('CMAKE_PREFIX_PATH', '').split(':'):
        if prefix.endswith('/devel') and os.path.isdir(
                os.path.join(prefix, '..', 'build')):
            return os.path.dirname(prefix)
    pytest.skip('not run from a sourced catkin devel space')


def import_in(setup):
    """Run IMPORT with only ``setup`` sourced; return its output lines."""
    proc = subprocess.run(
        ['env', '-i', 'HOME=' + os.environ.get('HOME', '/root'),
         'PATH=/usr/bin:/bin', 'bash', '-c',
         'source %s && cd / && python3 -c "%s"' % (setup, IMPORT)],
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
        universal_newlines=True, timeout=60)
    assert proc.returncode == 0, proc.stdout
    return proc.stdout.splitlines()


def check(lines, space):
    module, linear, angular = lines[-3:]
    assert module.startswith(space), module
    assert linear == str(LINEAR_FIELDS)
    assert angular == str(ANGULAR_FIELDS)


def test_cfg_modules_import_from_the_devel_space():
    ws = workspace()
    lines = import_in(os.path.join(ws, 'devel', 'setup.bash'))
    # In devel, rbx1_nav is catkin's relay package; it finds src/ and cfg/.
    check(lines, os.path.join(ws, 'devel'))


def test_cfg_modules_import_from_the_install_space():
    ws = workspace()
    build = subprocess.run(['flock', os.path.join(ws, '.build.lock'),
                            'make', '-C', os.path.join(ws, 'build'), 'install'],
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           universal_newlines=True, timeout=300)
    assert build.returncode == 0, build.stdout[-3000:]
    install = os.path.join(ws, 'install')
    check(import_in(os.path.join(install, 'setup.bash')), install)
