"""rbx1_nav: odometry-driven motion for a differential-drive robot.
In each subsystem a rospy-free module holds the logic and a ``*_ros.py`` wires it to ROS;
``transform_utils`` stays here for the book's scripts."""
import os

# Matrices here are 3x3 to 5x5: a multi-threaded BLAS only adds threads that spin between calls.
# Set before any module imports numpy; the environment wins.
for _name in ('OPENBLAS_NUM_THREADS', 'OMP_NUM_THREADS', 'MKL_NUM_THREADS'):
    os.environ.setdefault(_name, '1')
