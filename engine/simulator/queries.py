"""Read-only questions a Habitat program asks its simulator about the loaded scene.

:class:`SimulatorQueries` is mixed into :class:`engine.simulator.Simulator` and answers from
the simulator's own parts (scene graph, metadata mediator, physics world):

* ``scene_aabb``: the box around everything drawn (the root node's cumulative bounding box),
  a :class:`engine.mn.Range3D` in world meters;
* ``curr_scene_name``: the scene's simplified name, ``"NONE"`` for the empty scene
  (``scene_id`` ``"none"`` in any case);
* ``semantic_scene``: an empty :class:`engine.scene.semantic.SemanticScene` (rigidsim reads no
  semantic annotation files);
* ``metadata_mediator`` / ``get_metadata_mediator()``, and
  ``get_stage_initialization_template()``: a copy of the stage's template (None without a stage);
* ``get_physics_step_collision_summary()``: one line per touching pair of the last step,
  ``"[RigidObject, cubeSolid, id 1] vs [Stage, subpart 0], 4 points"``, as Habitat's Bullet backend
  formats it (``"(no active collision manifolds)"`` when nothing touches);
* ``_previous_step_time``: wall-clock seconds of the physics part of the last ``step()``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from engine import mn
from engine.bindings import stage_id
from engine.scene.semantic import SemanticScene

__all__ = ["SimulatorQueries", "is_none_scene", "simplified_scene_name"]

_STAGE_SUFFIXES = (".stage_config.json", ".scene_instance.json", ".json")


def is_none_scene(scene_id: str) -> bool:
    """True for Habitat's empty scene: ``"NONE"`` in any case (or an empty string)."""
    return scene_id.strip().lower() in ("none", "")


def simplified_scene_name(scene_id: str) -> str:
    """The file name of ``scene_id`` without folders and extension (``"NONE"`` if empty)."""
    if is_none_scene(scene_id):
        return "NONE"
    name = Path(scene_id).name
    for suffix in _STAGE_SUFFIXES:
        if name.endswith(suffix):
            return name[: -len(suffix)]
    return Path(name).stem


class SimulatorQueries:
    """Habitat's read-only simulator properties (mixed into ``Simulator``)."""

    config: Any
    root_node: Any
    _world: Any
    metadata_mediator: Any
    _stage_attributes: Any
    _semantic_scene: SemanticScene | None = None
    #: wall-clock seconds spent stepping physics in the last ``step()`` (Habitat's attribute)
    _previous_step_time: float = 0.0

    @property
    def scene_aabb(self) -> mn.Range3D:
        """World-frame box around every drawable in the scene graph (meters)."""
        return self.root_node.cumulative_bb

    @property
    def curr_scene_name(self) -> str:
        """The loaded scene's simplified name (``"NONE"`` for the empty scene)."""
        return simplified_scene_name(self.config.sim_cfg.scene_id)

    @property
    def semantic_scene(self) -> SemanticScene:
        """The scene's semantic annotation: empty in rigidsim (see :mod:`engine.scene.semantic`)."""
        if self._semantic_scene is None:
            self._semantic_scene = SemanticScene()
        return self._semantic_scene

    def get_metadata_mediator(self) -> Any:
        """The metadata mediator holding the active dataset's template managers."""
        return self.metadata_mediator

    def get_stage_initialization_template(self) -> Any:
        """A copy of the stage template the scene was built from, or None without a stage."""
        if self._stage_attributes is None:
            return None
        return self._stage_attributes.copy()

    def get_physics_step_collision_summary(self) -> str:
        """One line per touching pair of the last physics step (Habitat's Bullet format)."""
        counts: dict[tuple[int, int], int] = {}
        for point in self._world.get_physics_contact_points():
            # Bullet lists an object before the stage: order each pair (object, stage)
            a, b = int(point.object_id_a), int(point.object_id_b)
            pair = (a, b) if a != stage_id else (b, a)
            counts[pair] = counts.get(pair, 0) + 1
        if not counts:
            return "(no active collision manifolds)\n"
        lines = [
            f"[{self._debug_name(a)}] vs [{self._debug_name(b)}], {n} points"
            for (a, b), n in counts.items()
        ]
        return "\n".join(lines) + "\n"

    def _debug_name(self, object_id: int) -> str:
        """``Stage, subpart 0`` or ``RigidObject, <template handle>, id <id>`` (Habitat's
        names; rigidsim's stage is one merged mesh, so always subpart 0)."""
        if object_id == stage_id:
            return "Stage, subpart 0"
        obj = self._world.rigid_object_manager.get_object_by_id(object_id)
        handle = obj.creation_attributes.handle if obj is not None else "unknown"
        return f"RigidObject, {handle}, id {object_id}"
