"""The floors a physics robot (rbx1_nav.sim.physics) can drive on, and the
check of ~floor that names them (rbx1_nav.sim.params declares it). No rospy
here.
"""
from dataclasses import dataclass

from rbx1_nav.common.params import text

__all__ = ['Floor', 'FLOORS', 'floor_name']


@dataclass(frozen=True)
class Floor:
    """Contact of the wheels and casters with one kind of floor.

    ``wheel`` and ``caster`` are MuJoCo's friction triples (sliding, torsional
    in m, rolling in m); ``softness`` is the contact's time constant (s):
    a soft floor lets the wheels sink, which shortens their rolling radius.
    """
    wheel: tuple
    caster: tuple
    softness: float


#: The floors a robot can drive on. Carpet: more grip, a caster that drags,
#: rolling resistance, wheels that sink in by about a millimetre.
FLOORS = {
    'tile': Floor(wheel=(0.8, 0.001, 0.0002), caster=(0.02, 0.0005, 0.0001),
                  softness=0.004),
    'carpet': Floor(wheel=(1.0, 0.004, 0.0015), caster=(0.15, 0.002, 0.0005),
                    softness=0.02),
}


def floor_name(name, value):
    """``value`` as a key of :data:`FLOORS`, or ValueError naming ``name``."""
    value = text(name, value)
    if value not in FLOORS:
        raise ValueError('%s must be one of %s, got %.200r'
                         % (name, ', '.join(sorted(FLOORS)), value))
    return value
