"""``habitat_sim.scene``: the semantic scene, empty where a scene has no annotation file.

Habitat-sim reads semantic annotations (levels, regions, objects and their categories) from
dataset-specific files (mp3d ``.house``, replica ``info_semantic.json``, HM3D ``.txt``) into
``sim.semantic_scene``. rigidsim reads none of those formats (out of scope), so every scene's
semantic scene is the one Habitat builds for a scene without annotations: no levels, regions,
objects or categories, an empty ``aabb`` and an empty ``semantic_index_map``. The accessors are
Habitat's, so code that walks the hierarchy (``for level in scene.levels: ...``) runs and finds
nothing, and ``semantic_index_to_object_index`` raises ``KeyError`` naming the index.

Habitat's ``habitat_sim.scene`` also exports the scene graph classes (``SceneGraph``,
``SceneNode``); they live in :mod:`engine.scene.graph` and are importable from here too.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from engine import mn
from engine.scene.graph import SceneGraph, SceneNode

__all__ = [
    "BBox",
    "SceneGraph",
    "SceneNode",
    "SemanticCategory",
    "SemanticLevel",
    "SemanticObject",
    "SemanticRegion",
    "SemanticScene",
]


class BBox:
    """An axis-aligned box as Habitat's semantic types return it (``center``, ``size``).

    ``size`` (Habitat's name; ``sizes`` too) is ``max - min``; an empty box has zero size at
    the origin.
    """

    def __init__(self, min: Any = (0.0, 0.0, 0.0), max: Any = (0.0, 0.0, 0.0)) -> None:  # noqa: A002
        self.min = mn.to_vector3(min, "min")
        self.max = mn.to_vector3(max, "max")

    @property
    def center(self) -> mn.Vector3:
        return (self.min + self.max) * 0.5

    @property
    def size(self) -> mn.Vector3:
        return self.max - self.min

    sizes = size

    def __repr__(self) -> str:
        return f"BBox(center={self.center}, size={self.size})"


class SemanticCategory:
    """A category: ``index(mapping="")`` and ``name(mapping="")`` as in Habitat."""

    def __init__(self, index: int, name: str) -> None:
        self._index = int(index)
        self._name = str(name)

    def index(self, mapping: str = "") -> int:
        return self._index

    def name(self, mapping: str = "") -> str:
        return self._name


class SemanticObject:
    """An annotated object: ``id``, ``semantic_id``, ``category``, ``aabb``, ``region``."""

    def __init__(self, id: str, semantic_id: int, category: SemanticCategory, aabb: BBox) -> None:  # noqa: A002
        self.id = id
        self.semantic_id = int(semantic_id)
        self.category = category
        self.aabb = aabb
        self.region: SemanticRegion | None = None


class SemanticRegion:
    """An annotated region (a room): ``id``, ``category``, ``aabb``, ``objects``, ``level``."""

    def __init__(self, id: str, category: SemanticCategory, aabb: BBox) -> None:  # noqa: A002
        self.id = id
        self.category = category
        self.aabb = aabb
        self.objects: list[SemanticObject] = []
        self.level: SemanticLevel | None = None


class SemanticLevel:
    """An annotated floor: ``id``, ``aabb``, ``regions``, ``objects``."""

    def __init__(self, id: str, aabb: BBox) -> None:  # noqa: A002
        self.id = id
        self.aabb = aabb
        self.regions: list[SemanticRegion] = []
        self.objects: list[SemanticObject] = []


class SemanticScene:
    """Habitat's ``SemanticScene``; rigidsim builds it empty (see the module docstring)."""

    def __init__(self) -> None:
        self.aabb = BBox()
        self.categories: list[SemanticCategory] = []
        self.levels: list[SemanticLevel] = []
        self.regions: list[SemanticRegion] = []
        self.objects: list[SemanticObject] = []

    @property
    def semantic_index_map(self) -> dict[int, int]:
        """Semantic id -> index in ``objects``."""
        return {obj.semantic_id: i for i, obj in enumerate(self.objects)}

    def semantic_index_to_object_index(self, semantic_index: int) -> int:
        """The index in ``objects`` of the object with ``semantic_index`` (KeyError if none)."""
        index_map = self.semantic_index_map
        if semantic_index not in index_map:
            raise KeyError(
                f"no semantic object with semantic index {semantic_index!r} "
                f"(the scene has {len(self.objects)} annotated objects)"
            )
        return index_map[semantic_index]

    def get_regions_for_point(self, point: Any) -> list[int]:
        """Indices of the regions whose box contains ``point`` (3 floats, meters)."""
        p = np.asarray(mn.to_vector3(point, "point"))
        return [i for i, region in enumerate(self.regions) if _contains(region.aabb, p)]

    def get_weighted_regions_for_point(self, point: Any) -> list[tuple[int, float]]:
        """``(region index, weight)`` for the regions containing ``point``; weights sum to 1."""
        hits = self.get_regions_for_point(point)
        return [(i, 1.0 / len(hits)) for i in hits]

    def get_regions_for_points(self, points: Sequence[Any]) -> list[tuple[int, float]]:
        """For each region containing any of ``points``: (index, share of the points in it)."""
        if len(points) == 0:
            return []
        counts: dict[int, int] = {}
        for point in points:
            for i in self.get_regions_for_point(point):
                counts[i] = counts.get(i, 0) + 1
        return sorted(((i, n / len(points)) for i, n in counts.items()), key=lambda x: -x[1])


def _contains(box: BBox, point: np.ndarray) -> bool:
    return bool(np.all(point >= np.asarray(box.min)) and np.all(point <= np.asarray(box.max)))
