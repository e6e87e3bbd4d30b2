"""An ideal robot and a control loop for the course unit tests (no ROS)."""
import math

from rbx1_nav.motion.course.command import STOP
from rbx1_nav.transform_utils import Pose2D, normalize_angle

DT = 0.05  # the book's 20 Hz control rate


class IdealRobot(object):
    """A unicycle that follows each command exactly for one period.

    ``delay`` periods of latency model the command reaching the driver a
    cycle late; ``yaw_rate_bias`` (rad/s) models a robot that drifts.
    """

    def __init__(self, pose=Pose2D(0.0, 0.0, 0.0), delay=0, yaw_rate_bias=0.0):
        self.x, self.y, self.yaw = pose
        self.pending = [STOP] * delay
        self.bias = yaw_rate_bias

    @property
    def pose(self):
        return Pose2D(self.x, self.y, normalize_angle(self.yaw))

    def step(self, cmd, dt):
        """Run ``cmd`` (or the one the delay holds back) for ``dt`` s;
        return the velocity run."""
        self.pending.append(cmd)
        linear, angular = self.pending.pop(0)
        angular += self.bias if linear else 0.0
        mid = self.yaw + 0.5 * angular * dt
        self.x += linear * dt * math.cos(mid)
        self.y += linear * dt * math.sin(mid)
        self.yaw += angular * dt
        return linear, angular


def run(machine, robot, t0=100.0, limit=600.0, dt=DT, pose_delay=0,
        tell_age=True):
    """Run the course like the node does, every ``dt`` s; return
    (time, phase, command) rows.

    ``pose_delay`` periods of latency model a pose that reaches the node
    late; the node tells the course its age unless ``tell_age`` is false.
    The course hears the velocities the robot ran, as the node's odometry,
    from robots whose ``step`` returns them.
    """
    rows, t = [], t0
    poses = [robot.pose] * (pose_delay + 1)
    age = (pose_delay * dt,) if pose_delay and tell_age else ()
    while not machine.done:
        assert t - t0 < limit, 'course did not finish'
        phase_before = machine.phase
        cmd = machine.update(poses[0], t, *age)
        rows.append((t, phase_before if machine.phase == 'pause' else
                     machine.phase, cmd))
        ran = robot.step(cmd, dt)
        if ran is not None:  # robot models that tell the velocity they ran
            machine.stalls.velocity(t + dt, *ran)
        poses = poses[1:] + [robot.pose]
        t += dt
    return rows
