"""``magnum.meshtools``: Magnum's mesh-processing functions, as placeholders.

Magnum's ``meshtools`` turns ``trade.MeshData`` into other ``MeshData`` (index generation for
strips and fans, attribute filtering, interleaving, transforming). rigidsim never produces a
``trade.MeshData`` (:mod:`engine.mn.trade`), so each function raises ``NotImplementedError``
when called; ``InterleaveFlags`` is a real flag enum with Magnum's member names.
"""

from __future__ import annotations

import enum

from engine.core.placeholder import placeholder_function

__all__ = [
    "InterleaveFlags",
    "filter_only_attributes",
    "generate_indices",
    "interleave",
    "transform3d",
]

_MISSING = "Magnum's mesh tools work on magnum.trade.MeshData, which rigidsim never produces"
_INSTEAD = "engine.scene.assets.MeshData holds NumPy vertices and faces; transform them with NumPy"


class InterleaveFlags(enum.Flag):
    """Magnum's options of ``meshtools.interleave``."""

    NONE = 0
    PRESERVE_INTERLEAVED_ATTRIBUTES = 1
    PRESERVE_STRIDED_INDICES = 2


generate_indices = placeholder_function(
    "magnum.meshtools.generate_indices", _MISSING, _INSTEAD, module=__name__
)
filter_only_attributes = placeholder_function(
    "magnum.meshtools.filter_only_attributes", _MISSING, _INSTEAD, module=__name__
)
interleave = placeholder_function(
    "magnum.meshtools.interleave", _MISSING, _INSTEAD, module=__name__
)
transform3d = placeholder_function(
    "magnum.meshtools.transform3d", _MISSING, _INSTEAD, module=__name__
)
