"""A TurtleBot with real dynamics on MuJoCo: the model behind
fake_turtlebot.py and fake_fleet.py with ~physics true.

The kinematic model (rbx1_nav.sim.diff_drive) moves the base exactly as
commanded. Here the base is a rigid body of the URDF's mass and inertia
(urdf/turtlebot.urdf) on two driven wheels and two casters, on a floor with
friction, integrated by MuJoCo (DeepMind's physics engine, PyPI ``mujoco``)
every :data:`TIMESTEP` s:

* the **driver** turns each command into wheel speeds with the nominal
  wheel radius and separation; a wheel speed below ``motor_deadband`` is no
  command at all (the motor does not turn);
* each **motor** is a velocity servo (gain :data:`MOTOR_GAIN`) whose torque
  is limited to ``motor_torque`` and whose speed to ``max_wheel_speed``, so
  the base takes time to speed up, coasts when stopped and slows on carpet;
* the **wheels** touch the floor at one point each (spheres) with the
  friction of ``floor`` (rbx1_nav.sim.floors.FLOORS); their true radii are
  the nominal one times ``left_wheel_radius_error``/
  ``right_wheel_radius_error``, their true separation the nominal one times
  ``wheel_separation_error``;
* the **encoders** count ``encoder_ticks`` per revolution, and the driver's
  odometry comes from those counts exactly as in the kinematic model
  (diff_drive's multipliers and scale corrections apply the same way);
* the **gyro** measures the body's true yaw rate plus bias and noise.

The watchdog, speed clamps, acceleration limits (the driver's velocity
smoother) and command latency are the kinematic model's
(:class:`rbx1_nav.sim.diff_drive.DiffDriveFleet`); so are the fleet layout and
the scalar view of one robot. N robots of a fleet share one MuJoCo model
(they never collide with each other). No rospy here; ``mujoco`` is imported
only when a physics robot is made, so the kinematic robot works without it.
"""
import math
import os
import xml.etree.ElementTree as ElementTree
from dataclasses import dataclass

import numpy as np

from rbx1_nav.sim.diff_drive import DiffDriveConfig, DiffDriveFleet, columns
from rbx1_nav.sim.floors import FLOORS
from rbx1_nav.sim.params import PHYSICS_PARAMS, declared_fields

__all__ = ['PhysicsConfig', 'PhysicsFleet',
           'URDF', 'TIMESTEP', 'REST_SPEED', 'MOTOR_GAIN', 'ARMATURE', 'INSTALL_HINT', 'import_mujoco']

#: The package's URDF, in a source checkout (a node passes the installed
#: one's path, from rospkg).
URDF = os.path.join(os.path.dirname(os.path.abspath(__file__)),
                    *(3 * [os.pardir] + ['urdf', 'turtlebot.urdf']))
TIMESTEP = 0.002  # s, MuJoCo's integration step (500 Hz)
MOTOR_GAIN = 0.5  # N m per rad/s of wheel speed error, before the torque limit
#: kg m^2, a wheel's gear motor's inertia as the wheel feels it (a small
#: rotor times the gear ratio squared). Without it the wheel's own 5e-5 kg
#: m^2 under a stiff servo makes MuJoCo's contacts slip while braking.
ARMATURE = 0.002
SETTLE = 0.5      # s the robot is left to settle on the floor before time starts
#: m/s and rad/s: with every body slower than this and no wheel commanded,
#: the model rests and is not stepped. MuJoCo's soft contacts jitter a
#: robot at rest by ~1e-10 m/s; over a wait of any length that moved it by
#: nanometres, enough to tip an encoder tick and make a course's result
#: depend on how long the robot had stood. A stopped robot gets under it
#: in about 0.4 s.
REST_SPEED = 1e-6
INSTALL_HINT = ('the physics robot needs MuJoCo (Python >= 3.11): '
                '/usr/bin/python3 -m pip install mujoco (or `make build` in '
                'the package, which installs it); the kinematic robot (no '
                '~physics) works without it')


@declared_fields(PHYSICS_PARAMS)
class PhysicsConfig(DiffDriveConfig):
    """The kinematic model's parameters plus the physical ones
    (rbx1_nav.sim.params.PHYSICS_PARAMS).

    ``encoder_noise`` has no effect here: the encoders' error is their
    resolution (``encoder_ticks``) and the wheels' slip.
    """


@dataclass(frozen=True)
class Body:
    """What the physics model takes from the URDF (lengths in m, masses in
    kg, inertias in kg m^2): the base's centre of mass, mass and diagonal
    inertia; a wheel's mass and inertia about its axle and across; and the
    casters as (x, z, radius) relative to the axle's midpoint."""
    com: tuple
    base_mass: float
    base_inertia: tuple
    wheel_mass: float
    wheel_inertia: tuple
    casters: tuple

    @classmethod
    def from_urdf(cls, path):
        """The Body of urdf/turtlebot.urdf (or a robot with its links)."""
        root = ElementTree.parse(path).getroot()
        links = {link.get('name'): link for link in root.iter('link')}

        def inertial(name):
            element = links[name].find('inertial')
            inertia = element.find('inertia')
            origin = element.find('origin')
            xyz = (0.0, 0.0, 0.0) if origin is None else _floats(origin.get('xyz'))
            return (xyz, float(element.find('mass').get('value')),
                    tuple(float(inertia.get(k)) for k in ('ixx', 'iyy', 'izz')))

        com, base_mass, base_inertia = inertial('base_link')
        _, wheel_mass, (across, _, axle) = inertial('left_wheel_link')
        casters = []
        for joint in root.iter('joint'):
            child = links[joint.find('child').get('link')]
            sphere = child.find('collision/geometry/sphere')
            if joint.get('type') == 'fixed' and sphere is not None:
                x, _, z = _floats(joint.find('origin').get('xyz'))
                casters.append((x, z, float(sphere.get('radius'))))
        return cls(com, base_mass, base_inertia, wheel_mass, (axle, across),
                   tuple(casters))


def _floats(text_value):
    return tuple(float(v) for v in text_value.split())


def import_mujoco():
    """The mujoco module, or ImportError with :data:`INSTALL_HINT`."""
    try:
        import mujoco
    except ImportError:
        raise ImportError(INSTALL_HINT) from None
    return mujoco


def _triple(values):
    return '%g %g %g' % values


def mjcf(config, body, size):
    """The MuJoCo model (MJCF text) of ``size`` robots at the origin."""
    floor = FLOORS[config.floor]
    radius = config.wheel_radius
    half_track = 0.5 * config.wheel_separation * config.wheel_separation_error
    # The base's own mass scaled so the whole robot weighs config.mass.
    scale = (config.mass - 2 * body.wheel_mass) / body.base_mass
    if scale <= 0:
        raise ValueError('mass must exceed the two wheels\' %g kg, got %g'
                         % (2 * body.wheel_mass, config.mass))
    contact = 'condim="6" contype="1" conaffinity="2" solref="%g 1"' % floor.softness
    robots = []
    for i in range(size):
        casters = ''.join(
            '<geom type="sphere" size="%g" pos="%g 0 %g" friction="%s" %s/>'
            % (r, x, z, _triple(floor.caster), contact) for x, z, r in body.casters)
        wheels = ''.join(
            '<body name="r%d_%s" pos="0 %g 0"><joint name="r%d_%s" type="hinge" '
            'axis="0 1 0" frictionloss="0.002" armature="%g"/><inertial pos="0 0 0" mass="%g" '
            'diaginertia="%g %g %g"/><geom type="sphere" size="%g" friction="%s" '
            '%s/></body>' % (i, side, sign * half_track, i, side, ARMATURE, body.wheel_mass,
                             body.wheel_inertia[1], body.wheel_inertia[0],
                             body.wheel_inertia[1], radius * error,
                             _triple(floor.wheel), contact)
            for side, sign, error in (('left', 1, config.left_wheel_radius_error),
                                      ('right', -1, config.right_wheel_radius_error)))
        robots.append(
            '<body name="r%d" pos="0 0 %g"><freejoint/><inertial pos="%s" mass="%g" '
            'diaginertia="%s"/>%s%s</body>'
            % (i, radius, _triple(body.com), body.base_mass * scale,
               _triple(tuple(scale * c for c in body.base_inertia)), casters, wheels))
    motors = ''.join(
        '<velocity joint="r%d_%s" kv="%g" forcerange="-%g %g" ctrlrange="-%g %g"/>'
        % (i, side, MOTOR_GAIN, config.motor_torque, config.motor_torque,
           config.max_wheel_speed, config.max_wheel_speed)
        for i in range(size) for side in ('left', 'right'))
    # Elliptic friction cones with a high impratio: MuJoCo's soft friction
    # otherwise lets a wheel creep under a steady load (5 % at 1 cm/s).
    return ('<mujoco model="turtlebot"><option timestep="%g" integrator="implicitfast" '
            'cone="elliptic" impratio="10"/>'
            '<worldbody><geom type="plane" size="0 0 1" friction="0.0001 0 0" '
            'contype="2" conaffinity="1" solref="%g 1"/>%s</worldbody>'
            '<actuator>%s</actuator></mujoco>'
            % (TIMESTEP, floor.softness, ''.join(robots), motors))


class PhysicsFleet(DiffDriveFleet):
    """N robots with real dynamics (see the module docstring), read and
    commanded as a :class:`rbx1_nav.sim.diff_drive.DiffDriveFleet`.

    Raises ValueError for a bad configuration, a mass the wheels outweigh
    or motors too weak to move the robot on its floor, and ImportError
    (with :data:`INSTALL_HINT`) without MuJoCo.
    """

    QPOS, QVEL = 9, 8  # per robot: free joint (7, 6) and two wheels

    def __init__(self, size, config=None, urdf=URDF):
        super().__init__(size, config or PhysicsConfig())
        self._mujoco = import_mujoco()
        self.mujoco_version = self._mujoco.__version__
        body = Body.from_urdf(urdf)
        self._check_motors(self._mujoco.MjModel.from_xml_string(mjcf(self.config, body, 1)))
        self.model = self._mujoco.MjModel.from_xml_string(mjcf(self.config, body, size))
        self.data = self._mujoco.MjData(self.model)
        self._mujoco.mj_step(self.model, self.data, nstep=int(round(SETTLE / TIMESTEP)))
        self._elapsed = 0    # ns of ROS time stepped
        self._steps = 0      # MuJoCo steps taken since
        self._ticks = self._encoder_ticks()
        self._truth = None  # read from the state when asked (_true_state)

    @property
    def truth(self):
        """(N, 3): the bases' x, y, yaw, from MuJoCo's state."""
        return self._true_state()[0]

    @property
    def velocity(self):
        """(N, 2): the bases' (v, w) at the end of the last step."""
        return self._true_state()[1]

    def _state(self):
        return (self.data.qpos.reshape(self.size, self.QPOS),
                self.data.qvel.reshape(self.size, self.QVEL))

    def _encoder_ticks(self):
        wheels = self._state()[0][:, 7:9]
        return np.floor(wheels * self.config.encoder_ticks / (2.0 * math.pi))

    def _true_state(self):
        """(truth, velocity) from the bodies' state, computed once per step
        and only when asked: most steps nobody does (ground_truth without
        a subscriber)."""
        if self._truth is None:
            qpos, qvel = self._state()
            w, x, y, z = qpos[:, 3], qpos[:, 4], qpos[:, 5], qpos[:, 6]
            # In [-pi, pi] already: no wrap_angles.
            yaw = np.arctan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
            self._truth = columns(qpos[:, 0], qpos[:, 1], yaw)
            speed = qvel[:, 0] * np.cos(yaw) + qvel[:, 1] * np.sin(yaw)
            self._velocity = columns(speed, qvel[:, 5])
        return self._truth, self._velocity

    def _check_motors(self, model, speed=0.1, seconds=0.5):
        """ValueError unless one robot commanded ``speed`` m/s moves."""
        data = self._mujoco.MjData(model)
        self._mujoco.mj_step(model, data, nstep=int(round(SETTLE / TIMESTEP)))
        start = data.qpos[:2].copy()
        data.ctrl[:] = speed / self.config.wheel_radius
        self._mujoco.mj_step(model, data, nstep=int(round(seconds / TIMESTEP)))
        moved = float(np.hypot(*(data.qpos[:2] - start)))
        if moved < 0.1 * speed * seconds:
            cfg = self.config
            raise ValueError(
                'motor_torque %g N m cannot move the %g kg robot on %s: '
                'commanded %g m/s, it moved %.1f mm in %g s; raise '
                '~motor_torque' % (cfg.motor_torque, cfg.mass, cfg.floor, speed,
                                   1e3 * moved, seconds))

    def _move(self, v, w, dt):
        """The driver commands wheel speeds, MuJoCo integrates up to the
        step's end, and the encoders, odometry and gyro read the result."""
        cfg = self.config
        # As diff_drive_controller does, the driver turns (v, w) into wheel
        # speeds with its multiplied separation and radii: the multipliers
        # UMBmark prints straighten the robot's path, not only its odometry.
        half_track = 0.5 * cfg.wheel_separation * cfg.wheel_separation_multiplier
        radii = cfg.wheel_radius * np.array([cfg.left_wheel_radius_multiplier,
                                             cfg.right_wheel_radius_multiplier])
        wheels = columns(v - w * half_track, v + w * half_track) / radii
        wheels[np.abs(wheels) < cfg.motor_deadband] = 0.0
        self.data.ctrl[:] = wheels.ravel()
        self._elapsed += int(round(dt * 1e9))
        steps = int(round(self._elapsed * 1e-9 / TIMESTEP)) - self._steps
        resting = not wheels.any() and np.abs(self.data.qvel).max() < REST_SPEED
        if steps > 0 and not resting:
            self._mujoco.mj_step(self.model, self.data, nstep=steps)
            self._truth = None
        self._steps += max(steps, 0)
        ticks = self._encoder_ticks()
        self._update_odometry((ticks - self._ticks) * (2.0 * math.pi / cfg.encoder_ticks), dt)
        self._ticks = ticks
        self._update_gyro(self._state()[1][:, 5], dt)  # the body's yaw rate
