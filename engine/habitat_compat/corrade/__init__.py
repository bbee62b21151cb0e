"""The ``corrade`` names Habitat code touches (Corrade is Magnum's utility library).

With the import alias installed, ``import corrade`` gives this package. Habitat code uses only
``corrade.containers`` (a strided view over a Magnum mesh's data, in habitat-lab's receptacle
sampler); see :mod:`engine.habitat_compat.corrade.containers`.
"""

from __future__ import annotations

from engine.habitat_compat.corrade import containers

__all__ = ["containers"]
