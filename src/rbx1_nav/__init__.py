"""rbx1_nav: odometry-driven motion for a differential-drive robot.

One folder per subsystem: ``common`` (the ground the others stand on),
``motion``, ``sim``, ``sim_time``, ``calibration`` and ``estimation``. In
each, a rospy-free module holds the logic and is unit tested without a ROS
master; the ``*_ros.py`` module beside it wires that logic to ROS; a
script under ``nodes/`` declares its parameters and calls one entry point.
``rbx1_nav.transform_utils`` stays here, where the book's scripts import it.
"""
import os

# The filters' and simulators' matrices are 3x3 to 5x5: a multi-threaded
# BLAS only adds threads that spin between calls (on 2 cores pose_ekf's
# used four times the CPU of its filter). Before numpy is imported by any
# module here; a value set in the environment wins.
for _name in ('OPENBLAS_NUM_THREADS', 'OMP_NUM_THREADS', 'MKL_NUM_THREADS'):
    os.environ.setdefault(_name, '1')
