"""Checks that keep the package's wiring honest as scripts are added."""
import glob
import os
import re

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
NODES = sorted(glob.glob(os.path.join(ROOT, 'nodes', '*.py')))


def _cmake_installed_programs():
    text = open(os.path.join(ROOT, 'CMakeLists.txt')).read()
    block = re.search(r'catkin_install_python\(PROGRAMS(.*?)DESTINATION', text, re.S)
    return set(block.group(1).split())


def test_every_node_is_installed_and_executable():
    installed = _cmake_installed_programs()
    for path in NODES:
        rel = os.path.relpath(path, ROOT)
        assert rel in installed, '%s missing from catkin_install_python' % rel
        assert os.access(path, os.X_OK), '%s is not executable' % rel
        with open(path) as f:
            assert f.readline().strip() == '#!/usr/bin/env python3', rel


def test_installed_programs_exist():
    for rel in _cmake_installed_programs():
        assert os.path.isfile(os.path.join(ROOT, rel)), rel


def test_logic_modules_import_no_rospy():
    for path in glob.glob(os.path.join(ROOT, 'src', 'rbx1_nav', '*.py')):
        text = open(path).read()
        assert not re.search(r'^\s*(import|from)\s+rospy', text, re.M), path


def test_rostest_scripts_are_executable():
    for test_file in glob.glob(os.path.join(ROOT, 'test', '*.test')):
        for script in re.findall(r'type="([^"]+\.py)"', open(test_file).read()):
            hits = glob.glob(os.path.join(ROOT, 'test', '**', script), recursive=True)
            hits += glob.glob(os.path.join(ROOT, 'nodes', script))
            assert hits, '%s names %s, which is not in test/ or nodes/' % (
                test_file, script)
            assert all(os.access(h, os.X_OK) for h in hits), script
