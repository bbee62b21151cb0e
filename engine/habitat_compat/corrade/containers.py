"""``corrade.containers``: Corrade's array views, as placeholders.

Magnum's Python bindings hand out mesh and scene data as Corrade array views
(``StridedArrayView1D`` and friends: typed, strided windows onto a buffer). rigidsim never
produces them (it has no Magnum importer, :mod:`engine.mn.trade`); its meshes are NumPy
arrays. The names exist for annotations; constructing one raises ``NotImplementedError``.
"""

from __future__ import annotations

from engine.core.placeholder import Placeholder

__all__ = [
    "ArrayView",
    "MutableArrayView",
    "MutableStridedArrayView1D",
    "StridedArrayView1D",
    "StridedArrayView2D",
]

_MISSING = "Corrade array views over Magnum data are never produced (there is no Magnum importer)"
_INSTEAD = "NumPy arrays (rigidsim loads meshes with trimesh, see engine.scene.assets)"


class ArrayView(Placeholder):
    """Placeholder of Corrade's contiguous read-only array view."""

    habitat_name = "corrade.containers.ArrayView"
    missing = _MISSING
    instead = _INSTEAD


class MutableArrayView(ArrayView):
    """Placeholder of Corrade's contiguous mutable array view."""

    habitat_name = "corrade.containers.MutableArrayView"


class StridedArrayView1D(Placeholder):
    """Placeholder of Corrade's one-dimensional strided view (a mesh attribute, a scene field)."""

    habitat_name = "corrade.containers.StridedArrayView1D"
    missing = _MISSING
    instead = _INSTEAD


class MutableStridedArrayView1D(StridedArrayView1D):
    """Placeholder of Corrade's mutable one-dimensional strided view."""

    habitat_name = "corrade.containers.MutableStridedArrayView1D"


class StridedArrayView2D(Placeholder):
    """Placeholder of Corrade's two-dimensional strided view (an image's rows and pixels)."""

    habitat_name = "corrade.containers.StridedArrayView2D"
    missing = _MISSING
    instead = _INSTEAD
