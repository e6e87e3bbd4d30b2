"""rbx1_nav: odometry-driven motion for a differential-drive robot.

One folder per subsystem: ``common`` (the ground the others stand on),
``motion``, ``sim``, ``sim_time``, ``calibration`` and ``estimation``. In
each, a rospy-free module holds the logic and is unit tested without a ROS
master; the ``*_ros.py`` module beside it wires that logic to ROS; a
script under ``nodes/`` declares its parameters and calls one entry point.
``rbx1_nav.transform_utils`` stays here, where the book's scripts import it.
"""
