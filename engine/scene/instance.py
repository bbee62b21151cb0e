"""Scene instances: Habitat's ``*.scene_instance.json``, one stage plus placed objects.

A scene dataset (:mod:`engine.templates.metadata`) lists scene instance files under
``"scene_instances"``. Each file names a stage template and the objects to place in it::

    {
      "translation_origin": "asset_local",            # default for every instance below
      "stage_instance": {"template_name": "stages/frl_apartment_stage"},
      "object_instances": [
        {"template_name": "objects/chair", "motion_type": "DYNAMIC",
         "translation": [1.0, 0.5, -2.0], "rotation": [w, x, y, z],
         "non_uniform_scale": [1, 1, 1], "uniform_scale": 1.0, "mass_scale": 1.0}
      ],
      "default_lighting": "...", "navmesh_instance": "..."
    }

``template_name`` is matched as Habitat's ``getFullAttrNameFromStr`` does: an exact template
handle, else the first handle (sorted) that contains it. ``sim_cfg.scene_id`` names a scene
instance the same way (:func:`find_scene_instance`), else a ``.scene_instance.json`` file on
disk, else a stage (:func:`engine.simulator.loading.load_stage`).

Placing an object (Habitat's ``RigidObject::resetStateFromSceneInstanceAttr``): its template
is copied and scaled, ``scale' = scale * uniform_scale * non_uniform_scale``, and, with
``apply_scale_to_mass`` (default true), ``mass' = mass * prod(scale') * mass_scale``. Its
``translation`` is where the object's center of mass goes, unless the object is
"COM corrected": then it is where the asset's own origin goes, and with ``R`` the rotation and
``c`` the center of mass in the asset's frame the body's position is

    p = translation + R c

An instance is COM corrected when its ``translation_origin`` is ``asset_local``, or when it
gives none (``unknown``) and the scene's is ``asset_local``.
"""

from __future__ import annotations

import json
import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = [
    "SCENE_INSTANCE_SUFFIX",
    "SceneInstanceAttributes",
    "SceneObjectInstanceAttributes",
    "find_scene_instance",
    "full_handle_from_substring",
    "read_scene_instance",
]

SCENE_INSTANCE_SUFFIX = ".scene_instance.json"
#: Habitat's ``InstanceTranslationOriginMap`` keys (lower case), plus its default
TRANSLATION_ORIGINS = ("asset_local", "com", "unknown")
#: Habitat's ``MotionTypeNamesMap`` keys (lower case)
MOTION_TYPES = ("undefined", "static", "kinematic", "dynamic")


@dataclass
class SceneObjectInstanceAttributes:
    """One stage or object instance (Habitat's ``SceneObjectInstanceAttributes``)."""

    handle: str = ""
    translation: np.ndarray = field(default_factory=lambda: np.zeros(3))
    rotation: np.ndarray = field(default_factory=lambda: np.array([1.0, 0.0, 0.0, 0.0]))
    motion_type: str = "undefined"
    translation_origin: str = "unknown"
    uniform_scale: float = 1.0
    non_uniform_scale: np.ndarray = field(default_factory=lambda: np.ones(3))
    mass_scale: float = 1.0
    apply_scale_to_mass: bool = True
    #: None keeps the template's visibility
    is_instance_visible: bool | None = None

    @property
    def scale(self) -> np.ndarray:
        """The factor the template's scale is multiplied by (uniform times non-uniform)."""
        return self.uniform_scale * self.non_uniform_scale

    def is_com_corrected(self, scene_origin: str) -> bool:
        """True when ``translation`` places the asset's origin (module docstring)."""
        if self.translation_origin == "unknown":
            return scene_origin == "asset_local"
        return self.translation_origin == "asset_local"


@dataclass
class SceneInstanceAttributes:
    """A whole scene instance file (Habitat's ``SceneInstanceAttributes``)."""

    handle: str
    stage_instance: SceneObjectInstanceAttributes
    object_instances: list[SceneObjectInstanceAttributes] = field(default_factory=list)
    translation_origin: str = "unknown"
    default_lighting: str = ""
    navmesh_instance: str = ""
    semantic_scene_instance: str = ""
    #: how many ``articulated_object_instances`` the file lists (rigidsim does not load them)
    num_articulated_instances: int = 0


# -- reading -----------------------------------------------------------------------------------
def read_scene_instance(path: str | Path) -> SceneInstanceAttributes:
    """Read a ``*.scene_instance.json``; the handle is its resolved path.

    As Habitat: a missing ``stage_instance`` is an error (ValueError); a malformed entry or
    value is skipped with a warning.
    """
    path = Path(path).resolve()
    if not path.is_file():
        raise FileNotFoundError(f"scene instance file not found: {path}")
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as error:
        raise ValueError(f"scene instance {path} is not valid JSON: {error}") from error
    if not isinstance(data, dict):
        raise ValueError(
            f"scene instance {path} must hold a JSON object, got {type(data).__name__}"
        )
    stage = data.get("stage_instance")
    if not isinstance(stage, dict):
        raise ValueError(
            f"scene instance {path}: no JSON object 'stage_instance' (got {stage!r}), "
            f"so no stage can be created for this scene"
        )
    scene = SceneInstanceAttributes(
        handle=str(path),
        stage_instance=_read_instance(stage, f"{path.name} stage_instance"),
        translation_origin=_translation_origin(data, path.name),
        default_lighting=_string(data, "default_lighting", path.name),
        navmesh_instance=_string(data, "navmesh_instance", path.name),
        semantic_scene_instance=_string(data, "semantic_scene_instance", path.name),
    )
    objects = data.get("object_instances", [])
    if not isinstance(objects, list):
        _warn(f"{path.name}: 'object_instances' is not a JSON array ({objects!r}), ignored")
        objects = []
    for index, cell in enumerate(objects):
        if isinstance(cell, dict):
            scene.object_instances.append(_read_instance(cell, f"{path.name} object {index}"))
        else:
            _warn(f"{path.name}: object_instances[{index}] is not a JSON object, skipped")
    articulated = data.get("articulated_object_instances", [])
    scene.num_articulated_instances = len(articulated) if isinstance(articulated, list) else 0
    return scene


def _read_instance(cell: dict, where: str) -> SceneObjectInstanceAttributes:
    """One ``stage_instance`` / ``object_instances`` cell; bad values warn and keep defaults."""
    instance = SceneObjectInstanceAttributes(
        handle=_string(cell, "template_name", where),
        translation_origin=_translation_origin(cell, where),
    )
    motion = cell.get("motion_type")
    if motion is not None:
        if isinstance(motion, str) and motion.lower() in MOTION_TYPES:
            instance.motion_type = motion.lower()
        else:
            _warn(f"{where}: motion_type {motion!r} is not one of {MOTION_TYPES}, not set")
    translation = _numbers(cell, "translation", 3, where)
    if translation is not None:
        instance.translation = translation
    rotation = _numbers(cell, "rotation", 4, where)  # [w, x, y, z]
    if rotation is not None:
        norm = float(np.linalg.norm(rotation))
        if norm < 1e-12:
            _warn(f"{where}: rotation {rotation.tolist()} has zero length, identity used")
        else:
            instance.rotation = rotation / norm
    non_uniform = _numbers(cell, "non_uniform_scale", 3, where)
    if non_uniform is not None:
        instance.non_uniform_scale = non_uniform
    for name in ("uniform_scale", "mass_scale"):
        value = cell.get(name)
        if value is None:
            continue
        if isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value):
            setattr(instance, name, float(value))
        else:
            _warn(f"{where}: {name} {value!r} is not a finite number, not set")
    for name in ("apply_scale_to_mass", "is_instance_visible"):
        value = cell.get(name)
        if isinstance(value, bool):
            setattr(instance, name, value)
        elif value is not None:
            _warn(f"{where}: {name} {value!r} is not a boolean, not set")
    return instance


def _translation_origin(cell: dict, where: str) -> str:
    value = cell.get("translation_origin")
    if value is None:
        return "unknown"
    if isinstance(value, str) and value.lower() in TRANSLATION_ORIGINS:
        return value.lower()
    _warn(
        f"{where}: translation_origin {value!r} is not one of {TRANSLATION_ORIGINS}, unknown used"
    )
    return "unknown"


def _string(cell: dict, name: str, where: str) -> str:
    value = cell.get(name, "")
    if isinstance(value, str):
        return value
    _warn(f"{where}: {name} {value!r} is not a string, ignored")
    return ""


def _numbers(cell: dict, name: str, count: int, where: str) -> np.ndarray | None:
    """``cell[name]`` as ``count`` finite floats; None (and a warning when present) otherwise."""
    value = cell.get(name)
    if value is None:
        return None
    ok = (
        isinstance(value, list)
        and len(value) == count
        and all(isinstance(v, int | float) and not isinstance(v, bool) for v in value)
        and all(math.isfinite(v) for v in value)
    )
    if not ok:
        _warn(f"{where}: {name} {value!r} is not {count} finite numbers, not set")
        return None
    return np.array(value, dtype=float)


def _warn(message: str) -> None:
    warnings.warn(f"scene instance: {message}", stacklevel=4)


# -- finding -----------------------------------------------------------------------------------
def full_handle_from_substring(handles: list[str], name: str) -> str | None:
    """Habitat's ``getFullAttrNameFromStr``: ``name`` itself if it is a handle, else the first
    handle (sorted) containing it, else None."""
    if name in handles:
        return name
    matches = sorted(h for h in handles if name in h)
    return matches[0] if matches else None


def find_scene_instance(scene_handles: list[str], scene_id: str) -> str | None:
    """The scene instance file ``scene_id`` names (Habitat's
    ``getSceneInstanceAttributesByName``, first two cases): one of the dataset's scene
    instances containing it, else an existing ``*.scene_instance.json`` file (``scene_id`` or
    ``scene_id + ".scene_instance.json"``); None means ``scene_id`` names a stage."""
    if not isinstance(scene_id, str) or scene_id.strip().lower() in ("", "none"):
        return None
    found = full_handle_from_substring(scene_handles, scene_id)
    if found is None and scene_id:
        resolved = str(Path(scene_id).expanduser().resolve())
        found = full_handle_from_substring(scene_handles, resolved)
    if found is not None:
        return found
    for candidate in (scene_id, scene_id + SCENE_INSTANCE_SUFFIX):
        path = Path(candidate).expanduser()
        if path.name.endswith(SCENE_INSTANCE_SUFFIX) and path.is_file():
            return str(path.resolve())
    return None
