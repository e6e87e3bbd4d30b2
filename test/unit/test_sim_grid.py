"""A lockstep simulator's own grid (rbx1_nav.sim.loop_ros._Grid): at full
speed sim_clock grants only a course's ticks, and the simulator steps
through its grid on the way to each; those steps send only the sensor
messages (odom, the gyro, GPS), not tf or ground truth, which a node
reads at its ticks."""
from rbx1_nav.sim.loop_ros import _Grid
from rbx1_nav.sim_time.member import HANDLE

MS = 1000000  # ns


class Robot(object):
    step_time = None


def test_steps_on_the_way_to_a_grant_are_not_granted_steps():
    steps, robot = [], Robot()
    grid = _Grid(20 * MS, lambda stamp, granted: steps.append((stamp.to_nsec() // MS, granted)),
                 [robot], 'test')
    assert grid.step_to(HANDLE, 0, []) == 20 * MS
    # A 20 Hz course's tick at 50 ms: the 50 Hz grid's 20 and 40 ms on the way.
    assert grid.step_to(HANDLE, 50 * MS, []) == 60 * MS
    assert grid.step_to(HANDLE, 60 * MS, []) == 80 * MS  # a grid step granted
    assert steps == [(0, True), (20, False), (40, False), (50, True), (60, True)]
    assert robot.step_time == 60 * MS * 1e-9  # commands queued now count from there
