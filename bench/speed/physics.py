"""make bench's physics section: the kinematic and the physics robot
(MuJoCo) side by side, in simulated seconds per wall second.

Each model stepped alone without ROS (50 Hz, a command each step), each
robot alone under lockstep at full speed (``idle_speed:=1000000``:
unpaced; simulated seconds per wall second, read from /clock), the default
course at full speed on each, and how many physics robots one fake_fleet
keeps at 1x (``--robots``). Run by bench/bench.py (``--sections physics``).
"""
import os
import sys
import time

from common import ROOT, fmt, log
from graph import Graph, clock, course, describe
from speed import fleet_scale

#: (m, deg) a course on a physics robot of a fleet must end within to hold
#: 1x: about twice the error of one uncalibrated physics robot on carpet.
PHYSICS_LIMITS = (0.05, 5.0)


def alone(physics, seconds=10.0):
    """Simulated seconds per wall second of the robot alone under lockstep
    at full speed (no course: only the simulator asks for steps; sim_clock's
    idle pacing off)."""
    graph = Graph('fake_turtlebot.launch', dict(sim_speed='max', model='false',
                                               idle_speed='1000000',
                                               physics=str(physics).lower()))
    try:
        clock(graph)  # up and stepping
        start, wall = clock(graph), time.monotonic()
        time.sleep(seconds)
        return (clock(graph) - start) / (time.monotonic() - wall)
    finally:
        graph.close()


def model_only(physics, seconds=60.0, rate=50.0):
    """Simulated seconds per wall second of the model alone, no ROS: one
    robot stepped at ``rate`` Hz with a command every step."""
    sys.path.insert(0, os.path.join(ROOT, 'src'))
    from rbx1_nav.sim.diff_drive import DiffDriveFleet
    from rbx1_nav.sim.physics import PhysicsFleet
    fleet = PhysicsFleet(1) if physics else DiffDriveFleet(1)
    now = 0.0
    fleet.step(now)
    start = time.perf_counter()
    for _ in range(int(seconds * rate)):
        fleet.command(0, 0.15, 0.3, now)
        now += 1.0 / rate
        fleet.step(now)
    return seconds / (time.perf_counter() - start)


def physics(counts):
    """The kinematic and the physics robot side by side (see the module
    docstring), and the physics fleet at 1x."""
    rows = []
    for robot in (False, True):
        name = 'physics' if robot else 'kinematic'
        model = model_only(robot)
        log('physics: the %s model alone (no ROS): %.0fx' % (name, model))
        speedup = alone(robot)
        log('physics: the %s robot alone at max: %.0fx' % (name, speedup))
        result = course(physics=robot)
        log('physics: course on the %s robot at max: %s' % (name, describe(result)))
        rows.append(dict(robot=name, model=model, alone=speedup,
                         completed=result['status'] == 0,
                         course_speedup=(result['sim_s'] / result['wall_s']
                                         if result.get('wall_s') else None),
                         error_mm=result.get('error_mm'),
                         heading_deg=result.get('heading_deg')))
    fleet = fleet_scale.run_all(counts, modes=('fleet',), physics=True,
                                position_limit=PHYSICS_LIMITS[0],
                                heading_limit=PHYSICS_LIMITS[1], log=lambda r: log(
        'physics fleet %d robots: %d/%d completed, worst %.1f mm, %.2f deg, %.0f CPU s'
        % (r['n'], r['completed'], r['n'], r['true_mm'], r['true_deg'], r['cpu_total'])))
    return dict(robots=rows, fleet=fleet,
                fleet_holds=fleet_scale.largest_holding(fleet, 'fleet'))


def markdown(phys):
    """The section's tables, as lines."""
    out = ['## The physics robot (MuJoCo) beside the kinematic one', '',
           '| robot | model alone, no ROS | robot alone, lockstep unpaced | '
           'default course at max | final error (ground truth) |',
           '|---|---|---|---|---|']
    for r in phys['robots']:
        out.append('| %s | %s x | %s x | %s x | %s mm, %s deg |' % (
            r['robot'], fmt(r.get('model'), '%.0f'), fmt(r['alone'], '%.0f'),
            fmt(r['course_speedup']),
            fmt(r['error_mm']), fmt(r['heading_deg'], '%+.2f')))
    out += ['', 'Physics robots in one fake_fleet at 1x: up to %s hold (every '
            'course within %g mm, %g deg by its odometry and by ground truth: '
            'about twice what one uncalibrated physics robot misses by).' % (
                phys['fleet_holds'] or 'none', 1e3 * PHYSICS_LIMITS[0],
                PHYSICS_LIMITS[1]), '',
            '| robots | completed | worst true error | total CPU s | holds |',
            '|---|---|---|---|---|']
    for r in phys['fleet']:
        out.append('| %d | %d/%d | %s mm, %s deg | %s | %s |' % (
            r['n'], r['completed'], r['n'], fmt(r['true_mm']),
            fmt(r['true_deg'], '%.2f'), fmt(r['cpu_total'], '%.0f'),
            'yes' if r['holds'] else 'no'))
    out.append('')
    return out
