"""The pure model of the book's out-and-back (imported, not a node; no
ROS): the course run in plain Python on the simulator's own model
(rbx1_nav.sim.diff_drive.DiffDriveSim, the ideal robot), each command held
for one control period: what a graph under lockstep does when no message
is late, so its true end matches to 0.1 mm and 0.01 deg.

Used by test/rostest/lockstep_course_test.py and
test/rostest/book_lines_test.py; :func:`drive` (any course on any of the
simulator's robots, as the runner drives it) by
test/integration/test_physics_umbmark.py; :func:`turn_ratio` (the Eb that
makes a robot's odometry turn true) by it and by
test/integration/test_population.py.
"""
import math

from rbx1_nav.sim.diff_drive import DiffDriveSim
from rbx1_nav.motion.course.book import OUT_AND_BACK
from rbx1_nav.motion.course.settle import SETTLE_PARAMS, WAITING, Settle

#: The runner's settle_time and settle_timeout, at their defaults.
SETTLE = tuple(p.default for p in SETTLE_PARAMS)


def reference_end_poses(course_params, courses=1):
    """The true end pose (Pose2D) of each of ``courses`` runs of the course
    on one DiffDriveSim, each from where the last left the robot, as one
    course node after another drives it.

    ``course_params`` are the node's private parameters (angular_tolerance
    in degrees, rate in Hz; the rest as rbx1_nav.motion.course.book.OUT_AND_BACK's).
    """
    settings = dict(course_params)
    rate = settings.pop('rate', 20.0)
    settings.pop('tf_timeout', None)
    robot = DiffDriveSim()
    period_ns = int(round(1e9 / rate))
    tick = 0
    robot.step(0.0)
    ends = []
    for _ in range(courses):
        course = OUT_AND_BACK.course(**settings)
        while not course.done:
            cmd = course.update(robot.odom, tick * 1e-9)
            robot.command(cmd.linear, cmd.angular, tick * 1e-9)
            tick += period_ns
            robot.step(tick * 1e-9)
        ends.append(robot.truth)
    return ends


def reference_end_pose(course_params):
    """The true end pose of one course from the origin (see
    :func:`reference_end_poses`)."""
    return reference_end_poses(course_params)[0]


def drive(robot, course, now, period=0.05):
    """``course`` (rbx1_nav.motion.course.course.Course) on ``robot`` (a
    simulator's robot: ``odom``, ``truth``, ``command(v, w, t)``,
    ``fleet.step(t)``) from ``now`` (s), as the runner
    (rbx1_nav.motion.runner.runner_ros) drives it under lockstep: odometry read and
    a command sent every ``period`` s, each held for one period; at the end
    zero commanded until odometry stands still (rbx1_nav.motion.course.settle, at
    the runner's defaults). Returns (odometry's settled pose, the time reached)."""
    settle = None
    while settle is None or settle.update(robot.odom, now) == WAITING:
        if settle is None:
            command = course.update(robot.odom, now)
            if course.done:
                settle = Settle(robot.odom, now, *SETTLE)
        linear, angular = (0.0, 0.0) if settle else (command.linear, command.angular)
        robot.command(linear, angular, now)
        now += period
        robot.fleet.step(now)
    return settle.pose, now


def turn_ratio(robot, rate, turns=4, period=0.05):
    """Odometry's turn over the true turn of ``robot`` (a simulator's robot
    at rest, stepped to time 0) after ``turns`` turns in place of 90 deg by
    odometry at ``rate`` rad/s (negative: clockwise), each commanded every
    ``period`` s and followed by 1 s at rest: the Eb (UMBmark's
    wheel_separation_multiplier) that would make its odometry turn true."""
    now = odometry = truth = 0.0
    for _ in range(turns):
        true_start, previous, turned = robot.truth.yaw, robot.odom.yaw, 0.0
        rest = None
        while rest is None or now < rest:
            if rest is None and abs(turned) >= math.pi / 2:
                rest = now + 1.0
            robot.command(0.0, 0.0 if rest else rate, now)
            now += period
            robot.fleet.step(now)
            turned += math.remainder(robot.odom.yaw - previous, 2 * math.pi)
            previous = robot.odom.yaw
        odometry += turned
        truth += math.remainder(robot.truth.yaw - true_start, 2 * math.pi)
    return odometry / truth
