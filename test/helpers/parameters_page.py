"""docs/make_parameters.py, the generator of docs/parameters.md, loaded
as a module by the tests that check the docs against the nodes; and the
defaults a node declares, for the tests that run its logic in process."""
import importlib.util
import os

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def load():
    path = os.path.join(ROOT, 'docs', 'make_parameters.py')
    spec = importlib.util.spec_from_file_location('_make_parameters', path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def node_defaults(script):
    """{name: default} of the parameters nodes/``script`` declares."""
    node = load().load(os.path.join(ROOT, 'nodes', script))
    return {spec.name: spec.default for spec in node.PARAMS}
