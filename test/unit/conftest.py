"""Make the package's modules importable from the checkout, built or not,
and keep test runs from writing into the source tree (no .hypothesis/
example database; the Makefile and CMakeLists.txt also pass pytest
-p no:cacheprovider, so no .pytest_cache/)."""
import os
import sys
import tempfile

from hypothesis import configuration, settings

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'src'))
# Test plumbing of test/helpers/ (ideal_robot.py).
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'helpers'))

# The same examples on every run (derandomize), and no per-example time
# limit: the suite runs beside other work, and speed belongs in bench/.
settings.register_profile('rbx1_nav', database=None, derandomize=True,
                          deadline=None)
settings.load_profile('rbx1_nav')
# Hypothesis also caches Unicode tables in its storage directory.
configuration.set_hypothesis_home_dir(
    os.path.join(tempfile.gettempdir(), 'rbx1_nav-hypothesis'))
