"""What a ``Simulator`` loads when it is built: physics settings, the stage, its navmesh.

:class:`engine.simulator.simulator.Simulator` calls these in its constructor, in this order:

1. :func:`load_physics_config`: the ``*.physics_config.json`` of ``sim_cfg.physics_config_file``
   (Habitat's defaults, timestep 0.008 s and gravity -9.8 m/s^2, when the file is missing);
2. :func:`load_stage`: the stage template named by ``sim_cfg.scene_id`` (a template of the
   scene dataset, or one made for a bare ``.glb``/``.obj``/``.ply``) and its meshes in the
   world frame (Y up, meters); ``"NONE"`` (any case) is an empty world;
3. :func:`load_navmesh_beside_stage`: ``<stage stem>.navmesh`` next to the stage asset.

``Simulator.recompute_navmesh`` builds a navmesh from :func:`stage_triangles` (the stage
merged into one triangle soup) and, with ``include_static_objects``, the STATIC objects'
triangles appended by :func:`append_triangles`.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from engine import mn
from engine.logging import get_logger
from engine.physics.core.motion_type import MotionType
from engine.scene.assets import MeshData, load_meshes, merge_meshes
from engine.scene.instance import (
    SceneInstanceAttributes,
    SceneObjectInstanceAttributes,
    full_handle_from_substring,
)
from engine.templates.attributes import PhysicsManagerAttributes, StageAttributes
from engine.templates.managers import (
    ObjectAttributesManager,
    PhysicsAttributesManager,
    StageAttributesManager,
)
from navmesh import PathFinder

__all__ = [
    "append_triangles",
    "load_navmesh_beside_stage",
    "load_physics_config",
    "load_stage",
    "place_instance",
    "place_scene_objects",
    "stage_triangles",
]

# warnings point at the line that built the Simulator: this module <- Simulator._build
# <- Simulator.__init__ (or reconfigure) <- the caller
_CALLER_OF_SIMULATOR = 4


def load_physics_config(manager: PhysicsAttributesManager, path: str) -> PhysicsManagerAttributes:
    """The physics config at ``path``; Habitat's defaults (and a warning) when the file
    does not exist, as Habitat logs and creates default physics attributes."""
    try:
        return manager.load(path)
    except FileNotFoundError:
        warnings.warn(
            f"physics config {path!r} not found; using the default physics "
            f"settings (timestep 0.008 s, gravity -9.8 m/s^2)",
            stacklevel=_CALLER_OF_SIMULATOR,
        )
        return manager.load("")


def load_stage(
    stages: StageAttributesManager, scene_id: str, scale: np.ndarray | None = None
) -> tuple[StageAttributes | None, list[MeshData]]:
    """The stage's template and its meshes in the world frame (none for ``"NONE"``).

    ``scene_id`` is a stage template handle, or a part of one (Habitat's substring match, as
    a scene instance's ``template_name`` names its stage); any other name is an asset file,
    registered as a new template. ``scale`` multiplies the template's scale (a scene
    instance's ``uniform_scale * non_uniform_scale``).
    """
    if not isinstance(scene_id, str):
        raise TypeError(f"scene_id must be a string, got {scene_id!r}")
    if scene_id.strip().lower() in ("none", ""):
        # Habitat's empty scene ("NONE", any case): no stage, no navmesh, just a log line
        get_logger("sim").info("scene_id %r: an empty scene without a stage", scene_id)
        return None, []
    # a stage template of the dataset (a copy), else one made for the asset file
    handle = full_handle_from_substring(stages.get_template_handles(), scene_id)
    stage = stages.get_template_by_handle(handle) if handle is not None else None
    if stage is None:
        stage = stages.create_template_for_asset(scene_id)
        stages.register_template(stage)
    if scale is not None:
        stage.scale = np.asarray(stage.scale) * scale
    meshes = load_meshes(
        stage.render_asset_handle,
        up=stage.orient_up,
        front=stage.orient_front,
        scale=np.asarray(stage.scale) * 1.0,
        units_to_meters=stage.units_to_meters,
    )
    return stage, meshes


def place_scene_objects(
    scene: SceneInstanceAttributes, objects: Any, templates: ObjectAttributesManager, light: str
) -> list[Any]:
    """Add the scene instance's objects with ``objects`` (the rigid object manager) and put
    each at its instance pose (:mod:`engine.scene.instance`); the poses become the objects'
    reset poses. An unknown ``template_name`` raises KeyError before any object is added."""
    handles = templates.get_template_handles()
    chosen = []
    for instance in scene.object_instances:
        handle = full_handle_from_substring(handles, instance.handle)
        if handle is None:
            raise KeyError(
                f"scene instance {scene.handle}: object template {instance.handle!r} is not "
                f"in the dataset's object templates"
            )
        chosen.append(handle)
    placed = []
    for instance, handle in zip(scene.object_instances, chosen, strict=True):
        template = templates.get_template_by_handle(handle)
        assert template is not None  # the handle was found above
        template.scale = np.asarray(template.scale) * instance.scale
        if instance.apply_scale_to_mass:
            template.mass = template.mass * float(np.prod(np.asarray(template.scale)))
        template.mass = template.mass * instance.mass_scale
        if instance.is_instance_visible is not None:
            template.is_visibile = instance.is_instance_visible
        obj = objects.add_object_instance(template, light)
        place_instance(obj, instance, instance.is_com_corrected(scene.translation_origin))
        objects.save_reset_pose(obj)
        placed.append(obj)
    return placed


def place_instance(obj: Any, instance: SceneObjectInstanceAttributes, com_corrected: bool) -> None:
    """Pose ``obj`` as the instance says (``p = translation + R c`` when COM corrected), then
    set its motion type (after the pose: a STATIC object ignores pose setters)."""
    w, x, y, z = instance.rotation
    rotation = mn.Quaternion(mn.Vector3(x, y, z), w)
    translation = np.asarray(instance.translation, dtype=float)
    if com_corrected:
        translation = translation + np.asarray(rotation.transform_vector(obj.com))
    obj.translation = mn.Vector3(translation)
    obj.rotation = rotation
    if instance.motion_type != "undefined":
        obj.motion_type = MotionType[instance.motion_type.upper()]


def stage_triangles(stage_meshes: Sequence[MeshData]) -> tuple[np.ndarray, np.ndarray]:
    """The stage's triangles in the world frame, merged: ``(V, 3)`` meters, ``(F, 3)``."""
    if not stage_meshes:
        return np.zeros((0, 3)), np.zeros((0, 3), np.int64)
    merged = merge_meshes(stage_meshes)
    return merged.vertices, merged.faces


def append_triangles(
    vertices: np.ndarray, faces: np.ndarray, parts: Sequence[tuple[np.ndarray, np.ndarray]]
) -> tuple[np.ndarray, np.ndarray]:
    """``(vertices, faces)`` followed by every ``(V_k, 3), (F_k, 3)`` part, in one soup:
    the faces of part k are offset by the vertex count before it."""
    all_parts = [(vertices, faces), *parts]
    offsets = np.cumsum([0] + [len(v) for v, _ in all_parts[:-1]])  # first vertex of each part
    merged_vertices = np.concatenate([v for v, _ in all_parts])
    merged_faces = np.concatenate([f + o for (_, f), o in zip(all_parts, offsets, strict=True)])
    return merged_vertices, merged_faces


def load_navmesh_beside_stage(pathfinder: PathFinder, stage: StageAttributes | None) -> None:
    """Load ``<stage stem>.navmesh`` beside the stage's render asset, if there is one.

    As Habitat, a bad navmesh file is logged (a warning here) and the simulator runs
    without a navmesh.
    """
    if stage is None:
        return
    asset = Path(stage.render_asset_handle)
    navmesh_file = asset.with_name(asset.name.split(".")[0] + ".navmesh")
    if not navmesh_file.is_file():
        return
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        loaded = pathfinder.load_nav_mesh(str(navmesh_file))
    if not loaded:
        reason = "; ".join(str(w.message) for w in caught)
        warnings.warn(
            f"{navmesh_file} is not a valid navmesh, the simulator has no "
            f"navmesh (recompute_navmesh builds one): {reason}",
            stacklevel=_CALLER_OF_SIMULATOR,
        )
