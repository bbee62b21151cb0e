"""The mass ratio the solver holds, and the warning when a set mass goes beyond it.

Sequential impulses (and Bullet's solver alike) converge slowly when a heavy body rests on
a light one: the light body's contact rows see an effective mass ``m_light`` against
``m_heavy`` pressing down, and the few iterations of a step leave it a residual velocity of
the order of the ratio. Measured on Habitat's ``plane.glb`` and the demo apartment floor
(a 20 cm cube of 1 kg under a cube of ``ratio`` kg dropped 10 cm onto it, 3 cm off center,
turned 0.2 rad, 3 s): up to 20:1 the light cube moves less than 1 cm; up to 100:1 the
heavy cube stays on top and the light one slides 2-6 cm; from 200:1 (plane) or 1000:1
(apartment, and every ratio to 1e6 on both) the light cube is squeezed out sideways and
the heavy one lands on the floor. A heavy cube placed at rest, centered, on a light one
holds at every ratio to 1e6.

Habitat accepts any positive mass and so does rigidsim; beyond ``MAX_STABLE_MASS_RATIO``
between a dynamic object's mass and another live dynamic object's, a warning names both
masses, once per object (``rigidsim.physics`` logger).
"""

from __future__ import annotations

import numpy as np

from engine.logging import get_logger

from ..core.bodies import DYNAMIC

__all__ = ["MAX_STABLE_MASS_RATIO", "warn_beyond_stable_ratio"]

#: 1, the largest heavy : light mass ratio of two dynamic bodies that stays stacked
#: (module docstring for the measurement)
MAX_STABLE_MASS_RATIO = 100.0


def warn_beyond_stable_ratio(bodies, index: int, warned: set[int]) -> bool:
    """Log a warning when body ``index``'s mass is more than ``MAX_STABLE_MASS_RATIO``
    times another live dynamic body's, or less than its 1 / ``MAX_STABLE_MASS_RATIO``,
    unless ``index`` is in ``warned`` (the object manager's set: once per object; it is
    added there). True when it warned."""
    n = bodies.count
    others = bodies.body_alive[:n] & (bodies.body_motion_type[:n] == DYNAMIC)
    others[index] = False
    if bodies.body_motion_type[index] != DYNAMIC or not others.any():
        return False
    mass = float(bodies.body_mass[index])
    masses = bodies.body_mass[:n][others]
    lightest, heaviest = float(np.min(masses)), float(np.max(masses))
    ratio = max(mass / lightest, heaviest / mass)
    if ratio <= MAX_STABLE_MASS_RATIO or index in warned:
        return False
    warned.add(index)
    get_logger("physics").warning(
        "a dynamic body of %g kg beside one of %g kg: mass ratio %.3g:1 is beyond the "
        "%g:1 the solver holds; a heavy body dropped on a light one can squeeze it out "
        "(docs/reliability.md, 'Mass ratios')",
        mass,
        lightest if mass / lightest >= heaviest / mass else heaviest,
        ratio,
        MAX_STABLE_MASS_RATIO,
    )
    return True
