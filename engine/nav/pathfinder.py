"""``habitat_sim.nav.PathFinder`` as the simulator hands it out: points as ``mn.Vector3``.

:class:`navmesh.PathFinder` (the leaf library) answers with NumPy arrays. Habitat's bindings
return Magnum vectors, so Habitat code compares points with ``==``
(``assert point1 == point2`` after re-seeding) and reads ``.x``/``.y``; an array would give
an element-wise answer there. This subclass converts every returned point (and the bounds)
to :class:`engine.mn.Vector3`; everything else is inherited unchanged. ``Simulator.pathfinder``
is one of these; ``snap_point`` still returns NaN components when nothing is near.
"""

from __future__ import annotations

from typing import Any

import navmesh
from engine import mn

__all__ = ["PathFinder"]


class PathFinder(navmesh.PathFinder):
    """:class:`navmesh.PathFinder` returning ``mn.Vector3`` points (see the module docstring)."""

    def get_bounds(self) -> tuple[mn.Vector3, mn.Vector3]:  # type: ignore[override]
        low, high = super().get_bounds()
        return mn.Vector3(low), mn.Vector3(high)

    def snap_point(self, *args: Any, **kwargs: Any) -> mn.Vector3:  # type: ignore[override]
        return mn.Vector3(super().snap_point(*args, **kwargs))

    def get_random_navigable_point(self, *args: Any, **kwargs: Any) -> mn.Vector3:  # type: ignore[override]
        return mn.Vector3(super().get_random_navigable_point(*args, **kwargs))

    def get_random_navigable_point_near(self, *args: Any, **kwargs: Any) -> mn.Vector3:  # type: ignore[override]
        return mn.Vector3(super().get_random_navigable_point_near(*args, **kwargs))

    def try_step(self, *args: Any, **kwargs: Any) -> mn.Vector3:  # type: ignore[override]
        return mn.Vector3(super().try_step(*args, **kwargs))

    def try_step_no_sliding(self, *args: Any, **kwargs: Any) -> mn.Vector3:  # type: ignore[override]
        return mn.Vector3(super().try_step_no_sliding(*args, **kwargs))
