# Used by catkin_python_setup() only; do not run it by hand.
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(
    packages=['rbx1_nav', 'rbx1_nav.common', 'rbx1_nav.motion', 'rbx1_nav.motion.course',
              'rbx1_nav.motion.runner', 'rbx1_nav.motion.teleop', 'rbx1_nav.motion.plot',
              'rbx1_nav.sim', 'rbx1_nav.sim_time', 'rbx1_nav.calibration', 'rbx1_nav.estimation',
              'rbx1_nav.entry'],
    package_dir={'': 'src'},
))
