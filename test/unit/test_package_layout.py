"""Checks that keep the package's layout and wiring honest as code is added.

The rule: a subsystem's logic is a rospy-free module in
``src/rbx1_nav/<subsystem>/``; its ROS side is the ``*_ros.py`` module
beside it; a script in ``nodes/`` declares its parameters and calls one
entry point. Imports run one way (IMPORT_RULES).
"""
import ast
import glob
import os
import re

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
PACKAGE = os.path.join(ROOT, 'src', 'rbx1_nav')
NODES = sorted(glob.glob(os.path.join(ROOT, 'nodes', '*.py')))
SUBSYSTEMS = ('common', 'motion', 'sim', 'sim_time', 'calibration', 'estimation', 'entry')
#: Modules that talk to a ROS master or a running graph: only *_ros.py may
#: import them.
ROS_CLIENTS = ('rospy', 'tf2_ros', 'rosbag', 'rosgraph', 'rospkg',
               'dynamic_reconfigure')
#: subsystem -> the subsystems it must not import.
IMPORT_RULES = {
    'common': set(SUBSYSTEMS) - {'common'},
    'motion': {'sim', 'sim_time', 'estimation', 'calibration'},
    'sim': {'motion', 'calibration', 'estimation'},
    'sim_time': {'motion', 'sim', 'calibration', 'estimation'},
    'estimation': {'motion', 'sim', 'calibration'},
    'calibration': {'sim', 'sim_time', 'estimation'},
    # Above motion and sim_time: a node's entry point chooses a course's clock there.
    'entry': {'sim', 'calibration', 'estimation'},
}


def _modules():
    """(subsystem or None, path) of every module of the package."""
    for path in sorted(glob.glob(os.path.join(PACKAGE, '**', '*.py'), recursive=True)):
        rel = os.path.relpath(path, PACKAGE).split(os.sep)
        yield (rel[0] if len(rel) > 1 else None), path


def _imports(path):
    """Every module name ``path`` imports (absolute imports only)."""
    with open(path) as f:
        tree = ast.parse(f.read(), path)
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name
        elif isinstance(node, ast.ImportFrom) and node.module:
            yield node.module
            for alias in node.names:  # from rbx1_nav import sim
                yield node.module + '.' + alias.name


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


def test_one_folder_per_subsystem_and_no_flat_modules():
    """Only the package's __init__ and the book's transform_utils sit at the
    top; every folder is a subsystem that setup.py installs."""
    top = {os.path.basename(p) for p in glob.glob(os.path.join(PACKAGE, '*.py'))}
    assert top == {'__init__.py', 'transform_utils.py'}
    folders = {d for d in os.listdir(PACKAGE)
               if os.path.isdir(os.path.join(PACKAGE, d)) and d != '__pycache__'}
    assert folders == set(SUBSYSTEMS)
    setup = open(os.path.join(ROOT, 'setup.py')).read()
    for sub in SUBSYSTEMS:
        assert os.path.isfile(os.path.join(PACKAGE, sub, '__init__.py')), sub
        assert "'rbx1_nav.%s'" % sub in setup, 'setup.py does not install %s' % sub


def test_only_ros_modules_import_a_ros_client():
    for _, path in _modules():
        if path.endswith('_ros.py'):
            continue
        for name in _imports(path):
            assert name.split('.')[0] not in ROS_CLIENTS, (
                '%s imports %s: logic stays rospy-free; the ROS side goes in '
                'a *_ros.py module beside it' % (os.path.relpath(path, ROOT), name))


def test_imports_run_one_way():
    for sub, path in _modules():
        banned = IMPORT_RULES.get(sub, set(SUBSYSTEMS))  # top level: none
        if sub is None and path.endswith('__init__.py'):
            continue
        for name in _imports(path):
            parts = name.split('.')
            if parts[0] == 'rbx1_nav' and len(parts) > 1:
                assert parts[1] not in banned, '%s (%s) imports %s' % (
                    os.path.relpath(path, ROOT), sub or 'top level', name)
            assert parts[:2] != ['rbx1_nav', 'entry'] or sub == 'entry', (
                '%s imports %s: only nodes/ import entry' % (os.path.relpath(path, ROOT), name))


def test_the_pure_course_imports_no_ros_and_nothing_of_the_runner():
    """motion/course/ is what to drive and when a leg ends: the runner,
    teleop and the plot stand on it, never the other way round."""
    course = os.path.join(PACKAGE, 'motion', 'course')
    for path in glob.glob(os.path.join(course, '*.py')):
        for name in _imports(path):
            parts = name.split('.')
            assert parts[0] not in ROS_CLIENTS, '%s imports %s' % (path, name)
            if parts[:2] == ['rbx1_nav', 'motion'] and len(parts) > 2:
                assert parts[2] == 'course', '%s imports %s' % (
                    os.path.relpath(path, ROOT), name)


def _module_name(path):
    rel = os.path.relpath(path, os.path.dirname(PACKAGE))[:-3].split(os.sep)
    return '.'.join(rel[:-1] if rel[-1] == '__init__' else rel)


def _import_graph():
    """{module: the package's modules it imports}, drawn from every import
    (at the top of a module or inside a function)."""
    paths = {_module_name(path): path for _, path in _modules()}
    return {name: {imported for imported in _imports(path)
                   if imported in paths and imported != name}
            for name, path in paths.items()}


def test_no_import_circle():
    graph = _import_graph()
    done, path = set(), []

    def visit(name):
        if name in path:
            raise AssertionError('import circle: ' + ' -> '.join(
                path[path.index(name):] + [name]))
        if name in done:
            return
        path.append(name)
        for imported in sorted(graph[name]):
            if not imported.endswith('__init__') and imported != name.rsplit('.', 1)[0]:
                visit(imported)
        path.pop()
        done.add(name)

    for name in sorted(graph):
        visit(name)


#: The largest a class or a function may grow (lines, docstring included).
MAX_CLASS, MAX_FUNCTION = 250, 60


def test_no_class_or_function_too_long_to_read():
    found = []
    for path in [p for _, p in _modules()] + NODES:
        with open(path) as f:
            tree = ast.parse(f.read(), path)
        for node in ast.walk(tree):
            limit = (MAX_CLASS if isinstance(node, ast.ClassDef) else MAX_FUNCTION
                     if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) else None)
            lines = node.end_lineno - node.lineno + 1 if limit else 0
            if limit and lines > limit:
                found.append('%s: %s, %d lines (limit %d)' % (
                    os.path.relpath(path, ROOT), node.name, lines, limit))
    assert not found, found


def _main_call(statement):
    """The one call of ``if __name__ == '__main__':`` (a Call node), or None."""
    test = statement.test if isinstance(statement, ast.If) else None
    if not (isinstance(test, ast.Compare) and isinstance(test.left, ast.Name)
            and test.left.id == '__name__' and len(statement.body) == 1
            and not statement.orelse):
        return None
    only = statement.body[0]
    return only.value if isinstance(only, ast.Expr) and isinstance(only.value, ast.Call) else None


def _signal_reset(statement):
    """True for a top-level ``signal.signal(...)`` call."""
    call = statement.value if isinstance(statement, ast.Expr) else None
    return (isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute)
            and isinstance(call.func.value, ast.Name) and call.func.value.id == 'signal'
            and call.func.attr == 'signal')


#: What a node may call in a declaration: the package's helpers that declare
#: parameters.
DECLARATION_HELPERS = ('rbx1_nav.common.params.param',
                       'rbx1_nav.motion.runner.runner_params.common_params',
                       'rbx1_nav.calibration.scale_ros.node_params')


def _imported(tree):
    """{name: the module or object it stands for} of a module's imports."""
    found = {}
    for statement in tree.body:
        if isinstance(statement, ast.Import):
            for alias in statement.names:
                found[alias.asname or alias.name.split('.')[0]] = (
                    alias.name if alias.asname else alias.name.split('.')[0])
        elif isinstance(statement, ast.ImportFrom) and statement.module:
            for alias in statement.names:
                found[alias.asname or alias.name] = statement.module + '.' + alias.name
    return found


def _dotted(node, imported):
    """What a name, or a chain of attributes of one, stands for (through the
    imports: ``params.param`` is rbx1_nav.common.params.param); else None."""
    if isinstance(node, ast.Attribute):
        base = _dotted(node.value, imported)
        return base and base + '.' + node.attr
    return imported.get(node.id, node.id) if isinstance(node, ast.Name) else None


def _logic(node, imported):
    """The first part of ``node`` (an expression) that is logic, or None.
    Not logic: literals, names, calls of DECLARATION_HELPERS, and what puts
    these together: tuples, lists, dicts, a sign, ``+`` (declarations
    joined) and ``'text' % values`` (a help text)."""
    if isinstance(node, ast.Constant) or _dotted(node, imported) is not None:
        return None
    if isinstance(node, (ast.Tuple, ast.List)):
        parts = node.elts
    elif isinstance(node, ast.Dict):
        parts = [key for key in node.keys if key is not None] + node.values
    elif isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.UAdd, ast.USub)):
        parts = [node.operand]
    elif isinstance(node, ast.BinOp) and (isinstance(node.op, ast.Add) or (
            isinstance(node.op, ast.Mod) and isinstance(node.left, ast.Constant)
            and isinstance(node.left.value, str))):
        parts = [node.left, node.right]
    elif isinstance(node, ast.Call) and _dotted(node.func, imported) in DECLARATION_HELPERS:
        parts = node.args + [keyword.value for keyword in node.keywords]
    else:
        return node
    return next((found for found in (_logic(part, imported) for part in parts)
                 if found is not None), None)


def test_nodes_hold_no_rospy_logic_of_their_own():
    """A node file is its docstring, its imports (the package's, sys, signal),
    its declarations (NAME, PARAMS and their constants: literals, names and
    calls of DECLARATION_HELPERS) and one call of an entry point: the ROS
    plumbing lives in a *_ros.py module, the behaviour beside it."""
    for path in NODES:
        name = os.path.relpath(path, ROOT)
        with open(path) as f:
            source = f.read()
        tree = ast.parse(source, path)
        imported = _imported(tree)
        first, rest = tree.body[0], tree.body[1:]
        assert isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant), (
            '%s: no docstring' % name)
        calls = 0
        for statement in rest:
            if isinstance(statement, (ast.Import, ast.ImportFrom)):
                modules = ([alias.name for alias in statement.names]
                           if isinstance(statement, ast.Import) else [statement.module])
                for module in modules:
                    assert module in ('sys', 'signal') or module.split('.')[0] == 'rbx1_nav', (
                        '%s imports %s: a node imports the package (and sys); move its ROS '
                        'side into src/rbx1_nav/<subsystem>/*_ros.py' % (name, module))
            elif _signal_reset(statement):
                pass  # unless_running.py: Ctrl-C during its imports ends it quietly
            elif isinstance(statement, ast.Assign):
                assert all(isinstance(t, (ast.Name, ast.Tuple)) for t in statement.targets), (
                    '%s:%d: only names are declared' % (name, statement.lineno))
                logic = _logic(statement.value, imported)
                assert logic is None, (
                    '%s:%d: a declaration holds literals, names and calls of %s, not %r: '
                    'logic goes in src/rbx1_nav/<subsystem>/' % (
                        name, logic.lineno, ', '.join(DECLARATION_HELPERS),
                        ast.get_source_segment(source, logic)))
            else:
                assert _main_call(statement) is not None, (
                    '%s:%d: a node holds declarations and one call under __main__, not %s'
                    % (name, statement.lineno, type(statement).__name__))
                calls += 1
        assert calls == 1, '%s: %d calls under __main__' % (name, calls)


def test_rostest_scripts_are_executable():
    tests = glob.glob(os.path.join(ROOT, 'test', '**', '*.test'), recursive=True)
    assert tests
    for test_file in tests:
        for script in re.findall(r'type="([^"]+\.py)"', open(test_file).read()):
            hits = glob.glob(os.path.join(ROOT, 'test', '**', script), recursive=True)
            hits += glob.glob(os.path.join(ROOT, 'nodes', script))
            assert hits, '%s names %s, which is not in test/ or nodes/' % (
                test_file, script)
            assert all(os.access(h, os.X_OK) for h in hits), script


def test_every_rostest_sits_beside_its_script():
    """test/rostest/ and test/faults/ keep each .test beside the script it
    runs (ros_comm's test/test_rospy); helpers live in test/helpers/."""
    for folder in ('rostest', 'faults'):
        for test_file in glob.glob(os.path.join(ROOT, 'test', folder, '*.test')):
            scripts = re.findall(r'<test [^>]*type="([^"]+\.py)"', open(test_file).read())
            for script in scripts:
                assert os.path.isfile(os.path.join(os.path.dirname(test_file), script)), (
                    '%s runs %s, which is not beside it' % (test_file, script))
    assert not glob.glob(os.path.join(ROOT, 'test', '*.test'))


def _design_layout():
    """docs/design.md's Layout section: {path it names: the text of its bullet}."""
    with open(os.path.join(ROOT, 'docs', 'design.md')) as f:
        text = f.read()
    section = text.split('\n## Layout\n', 1)[1].split('\n## ', 1)[0]
    bullets = re.findall(r'^- `([^`]+)`:(.*?)(?=^- |\Z)', section, re.M | re.S)
    return {path: body for path, body in bullets}


def test_design_layout_names_every_module_of_each_subsystem():
    """Each subsystem's bullet, and each of its folders', names exactly the
    modules in that folder."""
    layout = _design_layout()
    for folder, _, files in os.walk(PACKAGE):
        rel = os.path.relpath(folder, PACKAGE)
        there = {f[:-3] for f in files if f.endswith('.py')} - {'__init__'}
        if rel == '.' or '__pycache__' in rel or not (there or rel in SUBSYSTEMS):
            continue
        key = 'src/rbx1_nav/%s/' % rel.replace(os.sep, '/')
        assert key in layout, 'docs/design.md Layout has no bullet for %s' % key
        named = set(re.findall(r'`([a-z_0-9]+)`', layout[key]))
        assert there - named == set(), 'docs/design.md Layout leaves out %s' % sorted(there - named)
        assert named - there == set(), 'docs/design.md Layout names %s, not in %s' % (
            sorted(named - there), key)


def test_design_layout_names_every_folder_of_test():
    layout = _design_layout()
    folders = {'test/%s/' % d for d in os.listdir(os.path.join(ROOT, 'test'))
               if os.path.isdir(os.path.join(ROOT, 'test', d)) and d != '__pycache__'}
    assert folders - set(layout) == set(), 'docs/design.md Layout leaves out %s' % sorted(
        folders - set(layout))
    for path in layout:
        assert os.path.exists(os.path.join(ROOT, path)), 'docs/design.md Layout names %s' % path


def test_the_design_cards_top_level_and_the_books_view_paths():
    """The card's top level is there, the views live in rviz/, and the
    package root has links to them, where the book's
    rviz -d `rospack find rbx1_nav`/sim.rviz looks (one copy of each)."""
    for name in ('package.xml', 'CMakeLists.txt', 'setup.py', 'nodes', 'src',
                 'launch', 'rviz', 'test'):
        assert os.path.exists(os.path.join(ROOT, name)), name
    views = sorted(os.path.basename(p) for p in glob.glob(os.path.join(ROOT, 'rviz', '*.rviz')))
    assert views == ['nav_ekf.rviz', 'sim.rviz']
    for view in views:
        at_root = os.path.join(ROOT, view)
        assert os.path.islink(at_root), '%s should link to rviz/%s' % (at_root, view)
        assert os.readlink(at_root) == os.path.join('rviz', view)


def test_a_course_nodes_help_says_truly_which_parameters_are_the_runners():
    """Each course node's docstring says '~rate and every one after it are
    the runner's': so they are."""
    import sys
    sys.path.insert(0, os.path.join(ROOT, 'test', 'helpers'))
    import parameters_page
    from rbx1_nav.motion.runner.runner_params import common_params
    runner = [spec.name for spec in common_params(rate=10)]
    assert runner[0] == 'rate'
    load = parameters_page.load().load
    for node in ('odom_out_and_back.py', 'nav_square.py', 'timed_out_and_back.py'):
        module = load(os.path.join(ROOT, 'nodes', node))
        assert "~rate and every one after it\nare the runner's" in module.__doc__, node
        names = [p.name for p in module.PARAMS]
        assert names[names.index('rate'):] == runner, node
