"""The fcl collision objects of every body: the shapes the narrow phase and the queries ask
fcl about, and the probes (shapes grown by ``STAGE_SPECULATIVE_DISTANCE``) that find the stage
triangles near a body.

:class:`CollisionObjects` is the world's ``collision_objects``; the collision stage
(:mod:`engine.physics.pipeline.collision_stage`) moves the objects of the pairs that ask fcl,
the narrow phase (:mod:`engine.physics.pipeline.narrow_phase`) and the contact test of
:mod:`engine.physics.objects.queries` read them. It lives below all three so that none of
them imports another for its type.
"""

from __future__ import annotations

from itertools import chain
from typing import Any

import fcl
import numpy as np

from ..core.bodies import STAGE_ID, Bodies
from ..core.settings import STAGE_SPECULATIVE_DISTANCE
from ..core.shapes import Shape, probe_geometry

__all__ = ["CollisionObjects"]


class CollisionObjects:
    """The fcl collision objects of every body, moved to a body's pose when fcl is about to
    be asked about it (:func:`move_fcl_users`, :meth:`move_shapes`; a box pair's contacts
    are analytic, so its objects may lag behind the bodies).

    ``shape_objects[i]``: one ``fcl.CollisionObject`` per shape of body ``i``;
    ``probe_objects[i]``: the same shapes grown by ``STAGE_SPECULATIVE_DISTANCE`` (None for
    the stage mesh), used to find stage triangles near a body (speculative contacts);
    ``shape_entries[i]``: ``(shape, shape object, probe object)`` of each shape of body ``i``.
    """

    def __init__(self) -> None:
        self.shape_objects: dict[int, list] = {}
        self.probe_objects: dict[int, list] = {}
        self.shape_entries: dict[int, list[tuple[Shape, Any, Any]]] = {}
        self.kinds: dict[int, tuple[str, ...]] = {}  # the kinds of every body's shapes
        # bodies of one box shape (single_box): its body_from_shape (4, 4) and half extents
        # (3,), by body index, so the box batch gathers them with one indexing call
        self.single_box = np.zeros(0, dtype=bool)
        self.box_offset, self.box_half = np.zeros((0, 4, 4)), np.zeros((0, 3))
        # every body's kinds as a small integer (``kind_code``, by body index) and the kinds
        # of each code (``code_kinds``), so a step's pairs are sorted by kinds in NumPy
        self.kind_code = np.zeros(0, dtype=np.int64)
        self.code_kinds: list[tuple[str, ...]] = []

    def install(self, index: int, shapes: list[Shape]) -> None:
        """Create the fcl objects of body ``index`` (placed by the next :meth:`move`)."""
        self.kinds[index] = tuple(s.kind for s in shapes)
        if len(self.single_box) <= index:
            size = max(index + 1, 2 * len(self.single_box))
            self.single_box = np.concatenate(
                [self.single_box, np.zeros(size - len(self.single_box), dtype=bool)]
            )
            self.box_offset = np.concatenate(
                [self.box_offset, np.zeros((size - len(self.box_offset), 4, 4))]
            )
            self.box_half = np.concatenate(
                [self.box_half, np.zeros((size - len(self.box_half), 3))]
            )
        if len(self.kind_code) <= index:
            grown = np.zeros(len(self.single_box), dtype=np.int64)
            grown[: len(self.kind_code)] = self.kind_code
            self.kind_code = grown
        if self.kinds[index] not in self.code_kinds:
            self.code_kinds.append(self.kinds[index])
        self.kind_code[index] = self.code_kinds.index(self.kinds[index])
        self.single_box[index] = len(shapes) == 1 and shapes[0].kind == "box"
        if self.single_box[index]:
            self.box_offset[index] = shapes[0].body_from_shape
            self.box_half[index] = np.array(shapes[0].geometry.side, dtype=np.float64) / 2.0
        self.shape_objects[index] = [
            fcl.CollisionObject(s.geometry, fcl.Transform()) for s in shapes
        ]
        self.probe_objects[index] = [
            None
            if s.kind == "mesh"
            else fcl.CollisionObject(probe_geometry(s, STAGE_SPECULATIVE_DISTANCE), fcl.Transform())
            for s in shapes
        ]
        entries = zip(shapes, self.shape_objects[index], self.probe_objects[index], strict=True)
        self.shape_entries[index] = list(entries)

    def remove(self, index: int) -> None:
        self.shape_objects.pop(index, None)
        self.probe_objects.pop(index, None)
        self.shape_entries.pop(index, None)
        self.kinds.pop(index, None)
        if index < len(self.single_box):
            self.single_box[index] = False

    def __contains__(self, index: int) -> bool:
        return index in self.shape_objects

    def move_shapes(self, bodies: Bodies, indices: list[int], rotation: np.ndarray) -> None:
        """Move the shape objects (not the probes) of bodies ``indices`` (stage excluded) to
        their poses (``rotation (n, 3, 3)``: every body's matrix)."""
        index = np.array(sorted(set(indices) - {STAGE_ID}), dtype=np.int64)
        if len(index):
            self.move(bodies, index, rotation[index], np.zeros(len(index), dtype=bool))

    def move(
        self,
        bodies: Bodies,
        indices: np.ndarray,
        rotations: np.ndarray,
        with_probe: np.ndarray | None = None,
    ) -> None:
        """Move the fcl objects of bodies ``indices (k,)`` (rotation matrices ``(k, 3, 3)``):
        all shape poses ``world_from_shape = world_from_body @ body_from_shape`` at once.

        ``with_probe (k,)`` bool: whose probe objects move too (default all; the narrow
        phase asks a probe only about a pair with the stage)."""
        owners, objects, offsets = [], [], []
        probes = [True] * len(indices) if with_probe is None else with_probe.tolist()
        for k, index in enumerate(indices.tolist()):
            for shape, obj, probe in zip(
                bodies.shapes[index],
                self.shape_objects[index],
                self.probe_objects[index],
                strict=True,
            ):
                owners.append(k)
                objects.append((obj, probe if probes[k] else None))
                offsets.append(shape.body_from_shape)
        if not owners:
            return
        offset = np.array(offsets)
        r = rotations[owners]
        # world_from_shape = [R R_off | R t_off + x] for every shape at once
        shape_rotation = r @ offset[:, :3, :3]
        shape_position = (r @ offset[:, :3, 3:])[..., 0] + bodies.body_position[indices[owners]]
        for (obj, probe), rot, pos in zip(objects, shape_rotation, shape_position, strict=True):
            obj.setRotation(rot)
            obj.setTranslation(pos)
            if probe is not None:
                probe.setRotation(rot)
                probe.setTranslation(pos)


def pairs_as_array(pairs: list[tuple[int, int]]) -> np.ndarray:
    """``(p, 2)`` int64 array of a list of body pairs, read through one flat iterator (about
    twice as fast as ``np.array`` on a list of tuples)."""
    flat = np.fromiter(chain.from_iterable(pairs), dtype=np.int64, count=2 * len(pairs))
    return flat.reshape(-1, 2)
