"""Template libraries: register, look up, copy, lock and remove attribute templates.

Mirrors ``habitat_sim.attributes_managers``. A manager maps **handles** (a config file's full
path, or a primitive's name such as ``cubeSolid``) to templates with integer **ids**.
Habitat's contract, kept here:

* ``get_template_by_id`` / ``get_template_by_handle`` return **copies**; edits take effect only
  after ``register_template``, which overwrites an existing handle keeping its id, or adds the
  template with a new id, and writes that id (and the handle it was registered under) into
  the caller's template, as Habitat's C++ manager does with the shared template.
* Lookups of unknown handles or ids return ``None`` (id lookups ``-1``, handle lookups
  ``""``), removing or overwriting a locked template returns ``None`` / ``-1``: Habitat's
  return values, with a ``UserWarning`` where Habitat logs.
* ``get_template_handles(search_str, contains=True)`` matches case-insensitively and is sorted.
* ``load_configs(path, save_as_defaults=False)``: a folder loads every
  ``*.object_config.json`` directly in it (sorted, not recursive); a path without the extension
  gets it appended; re-loading a file keeps its id; ``save_as_defaults`` makes the loaded
  templates undeletable (Habitat's "default" templates).
* Locked templates cannot be overwritten or removed; the primitive defaults are locked.

Managers need no simulator: ``ObjectAttributesManager()`` works on its own.
"""

from __future__ import annotations

import random
import warnings
from pathlib import Path
from typing import Generic, TypeVar

import numpy as np

from engine.scene.primitives import (
    PRIMITIVE_ASSET_HANDLES,
    is_primitive_handle,
    parse_primitive_handle,
)
from engine.templates.attributes import (
    AbstractAttributes,
    ObjectAttributes,
    PhysicsManagerAttributes,
    PrimitiveAssetAttributes,
    StageAttributes,
    checked_path,
)

__all__ = [
    "PRIMITIVE_ASSET_HANDLES",
    "AssetAttributesManager",
    "ObjectAttributesManager",
    "PhysicsAttributesManager",
    "StageAttributesManager",
]

# Scale of the primitive-based object templates: a cube object is 0.2 m across.
PRIMITIVE_OBJECT_SCALE = 0.1

T = TypeVar("T", bound=AbstractAttributes)


def unknown_handle_message(manager: _AttributesManager, handle: str) -> str:
    """The warning for a handle (or search text) that names no template: the full handles that
    contain it (handles of loaded configs are file paths), or, where none does, the templates
    there are and that the config must be loaded first."""
    known = manager._matching_handles("", True)
    matching = manager._matching_handles(handle, True)
    if matching and handle not in matching:
        shown = ", ".join(repr(h) for h in matching[:5]) + (" ..." if len(matching) > 5 else "")
        return (
            f"no template with handle {handle!r}; handles are full names, and these contain "
            f"it: {shown} (get_template_handles({handle!r})[0] is the first)"
        )
    files = [h for h in known if h not in PRIMITIVE_ASSET_HANDLES]
    what = f"{len(files)} loaded from config files" if files else "none loaded from config files"
    return (
        f"no template handle contains {handle!r} ({len(known)} templates, {what}): load its "
        f"config first, with load_configs(<path of its *{manager.config_suffix} or its folder>)"
    )


class _AttributesManager(Generic[T]):
    """Handle <-> id bookkeeping shared by every template manager."""

    template_class: type[T]  # the template class of each manager (set by the subclasses)
    config_suffix = ".json"

    def __init__(self) -> None:
        self._templates: dict[str, T] = {}
        self._ids: dict[str, int] = {}
        self._locked: set[str] = set()
        self._undeletable: set[str] = set()
        self._next_id = 0

    # -- queries --------------------------------------------------------------------------------
    def get_num_templates(self) -> int:
        return len(self._templates)

    def get_library_has_handle(self, handle: str) -> bool:
        return handle in self._templates

    def get_library_has_id(self, template_id: int) -> bool:
        return template_id in self._ids.values()

    def get_template_id_by_handle(self, handle: str) -> int:
        """The id of ``handle``, or -1 (Habitat's ``ID_UNDEFINED``) with a warning."""
        if handle not in self._ids:
            warnings.warn(unknown_handle_message(self, handle), stacklevel=2)
            return -1
        return self._ids[handle]

    get_template_ID_by_handle = get_template_id_by_handle  # noqa: N815 - Habitat's older name

    def get_template_handle_by_id(self, template_id: int) -> str:
        """The handle of ``template_id``, or ``""`` with a warning."""
        for handle, known_id in self._ids.items():
            if known_id == template_id:
                return handle
        warnings.warn(f"no template with id {template_id!r}", stacklevel=2)
        return ""

    get_template_handle_by_ID = get_template_handle_by_id  # noqa: N815

    def get_template_handles(self, search_str: str = "", contains: bool = True) -> list[str]:
        """Handles that contain (or, with ``contains=False``, do not contain) ``search_str``,
        compared case-insensitively, sorted case-insensitively. When no handle contains a
        non-empty ``search_str`` the list is empty, as Habitat's, with a warning saying which
        templates there are and that a config file must be loaded first (``load_configs``)."""
        handles = self._matching_handles(search_str, contains)
        if not handles and search_str and contains:
            warnings.warn(unknown_handle_message(self, search_str), stacklevel=2)
        return handles

    def _matching_handles(self, search_str: str, contains: bool) -> list[str]:
        """``get_template_handles`` without its warning (for the other lookups by substring)."""
        needle = search_str.lower()
        chosen = [h for h in self._templates if (needle in h.lower()) == contains]
        return sorted(chosen, key=lambda h: (h.lower(), h))

    def get_random_template_handle(self) -> str:
        return random.choice(self._matching_handles("", True))

    # -- copies in and out ----------------------------------------------------------------------
    def get_template_by_handle(self, handle: str) -> T | None:
        """A copy of the template registered under ``handle``; None (warning) if unknown."""
        if handle not in self._templates:
            warnings.warn(unknown_handle_message(self, handle), stacklevel=2)
            return None
        return self._templates[handle].copy()

    def get_template_by_id(self, template_id: int) -> T | None:
        """A copy of the template with id ``template_id``; None (warning) if unknown."""
        handle = self._handle_of(template_id)
        if handle is None:
            warnings.warn(f"no template with id {template_id!r}", stacklevel=2)
            return None
        return self._templates[handle].copy()

    def _handle_of(self, template_id: int) -> str | None:
        return next((h for h, known in self._ids.items() if known == template_id), None)

    get_template_by_ID = get_template_by_id  # noqa: N815 - Habitat's older spelling

    def get_templates_by_handle_substring(self, search_str: str = "", contains: bool = True):
        handles = self._matching_handles(search_str, contains)
        return {h: self.get_template_by_handle(h) for h in handles}

    def create_new_template(self, handle: str, register_template: bool = False) -> T:
        """A template with default values (registered too if asked)."""
        template = self.template_class(handle)
        if register_template:
            self.register_template(template)
        return template

    def register_template(
        self, template: T, specified_handle: str = "", force_registration: bool = False
    ) -> int:
        """Store a copy of ``template``; an existing handle keeps its id. Returns the id.

        As in Habitat, the id (and ``specified_handle``, if given) is written into the
        caller's ``template`` too. A locked handle is not overwritten: -1 with a warning.
        ``force_registration`` is accepted for Habitat's signature (every valid template
        registers here).
        """
        if not isinstance(template, self.template_class):
            raise TypeError(
                f"expected a {self.template_class.__name__}, got {type(template).__name__}"
            )
        if not isinstance(specified_handle, str):
            raise TypeError(f"specified_handle must be a str, got {specified_handle!r}")
        handle = specified_handle or template.handle
        template.check_frame(handle)
        if not handle:
            raise ValueError("a template needs a non-empty handle to be registered")
        if handle in self._locked:
            warnings.warn(f"template {handle!r} is locked and was not overwritten", stacklevel=2)
            return -1
        template_id = self._ids.get(handle)
        if template_id is None:
            template_id = self._next_id
            self._next_id += 1
        template.handle = handle
        template.template_id = template_id
        template._mark_paths_clean()
        self._templates[handle] = template.copy()
        self._ids[handle] = template_id
        return template_id

    # -- removal and locks ----------------------------------------------------------------------
    def remove_template_by_handle(self, handle: str) -> T | None:
        """Remove and return the template; None (warning) if unknown, locked or a default."""
        if handle not in self._templates:
            warnings.warn(f"no template with handle {handle!r}", stacklevel=2)
            return None
        if handle in self._locked or handle in self._undeletable:
            warnings.warn(f"template {handle!r} is locked and was not removed", stacklevel=2)
            return None
        return self._pop(handle)

    def _pop(self, handle: str) -> T:
        """Remove a registered template (the caller checked it may be removed)."""
        self._ids.pop(handle)
        return self._templates.pop(handle)

    def remove_template_by_id(self, template_id: int) -> T | None:
        handle = self._handle_of(template_id)
        if handle is None:
            warnings.warn(f"no template with id {template_id!r}", stacklevel=2)
            return None
        return self.remove_template_by_handle(handle)

    def remove_templates_by_str(self, search_str: str = "", contains: bool = True) -> list[T]:
        """Remove every unlocked, deletable template whose handle matches; returns them."""
        removable = [
            h
            for h in self._matching_handles(search_str, contains)
            if h not in self._locked and h not in self._undeletable
        ]
        return [self._pop(h) for h in removable]

    def remove_all_templates(self) -> None:
        self.remove_templates_by_str("", True)

    def set_template_lock(self, handle: str, lock: bool) -> bool:
        """Lock or unlock ``handle``; False (warning) if there is no such template."""
        if handle not in self._templates:
            warnings.warn(f"no template with handle {handle!r}", stacklevel=2)
            return False
        (self._locked.add if lock else self._locked.discard)(handle)
        return True

    def set_lock_by_substring(
        self, lock: bool, search_str: str = "", contains: bool = True
    ) -> list[str]:
        """Lock or unlock every template whose handle matches; returns their handles."""
        handles = self._matching_handles(search_str, contains)
        for handle in handles:
            self.set_template_lock(handle, lock)
        return handles

    def get_template_lock(self, handle: str) -> bool:
        return handle in self._locked

    def get_undeletable_handles(self) -> list[str]:
        return sorted(self._undeletable)

    # -- files ----------------------------------------------------------------------------------
    def _config_files(self, path: str | Path) -> list[Path]:
        """The config files ``path`` names: a folder's, a file, or a file missing its suffix."""
        path = checked_path(path).expanduser()
        if path.is_dir():
            return sorted(path.glob(f"*{self.config_suffix}"))
        if path.is_file() and path.name.endswith(self.config_suffix):
            return [path]
        for suffix in (self.config_suffix, ".json"):  # "x" or "x.object_config" -> full name
            with_suffix = path.with_name(path.name + suffix)
            if with_suffix.is_file() and with_suffix.name.endswith(self.config_suffix):
                return [with_suffix]
        raise FileNotFoundError(f"no {self.config_suffix} config at {path}")

    def load_configs(self, path: str | Path, save_as_defaults: bool = False) -> list[int]:
        """Load every config ``path`` names; returns their template ids (in file order).

        All files are parsed before any is registered, so a bad file registers nothing.
        ``save_as_defaults`` makes the loaded templates undeletable (Habitat's defaults).
        """
        if not isinstance(save_as_defaults, bool | np.bool_):
            raise TypeError(f"save_as_defaults must be a bool, got {save_as_defaults!r}")
        templates = [self.template_class.from_json_file(f) for f in self._config_files(path)]
        ids = [self.register_template(t) for t in templates]
        if save_as_defaults:
            self._undeletable.update(t.handle for t in templates)
        return ids


class AssetAttributesManager(_AttributesManager[PrimitiveAssetAttributes]):
    """The primitive asset templates (Magnum primitives), locked defaults included."""

    template_class = PrimitiveAssetAttributes

    def __init__(self) -> None:
        super().__init__()
        for handle in PRIMITIVE_ASSET_HANDLES:
            self.register_template(PrimitiveAssetAttributes(handle))
            self._undeletable.add(handle)

    def register_template(
        self,
        template: PrimitiveAssetAttributes,
        specified_handle: str = "",
        force_registration: bool = False,
    ) -> int:
        """As for every manager, but an invalid primitive (``is_valid_template`` False)
        is refused: -1 with a warning, as Habitat builds no primitive from it."""
        if isinstance(template, PrimitiveAssetAttributes) and not template.is_valid_template:
            warnings.warn(
                f"primitive template {template.handle!r} is not valid; not registered", stacklevel=2
            )
            return -1
        return super().register_template(template, specified_handle, force_registration)

    def get_default_template_handle(self, primitive_class: str, is_wireframe: bool = False) -> str:
        """The default handle of a primitive class (``"Cube"``, ``"Icosphere"``...)."""
        for handle in PRIMITIVE_ASSET_HANDLES:
            template = self._templates[handle]
            same_class = template.primitive_class == primitive_class
            if same_class and template.is_wireframe == is_wireframe:
                return handle
        raise KeyError(f"unknown primitive class {primitive_class!r}")

    def _default(self, primitive_class: str, is_wireframe: bool) -> PrimitiveAssetAttributes:
        """A copy of a default primitive template (always registered: undeletable)."""
        handle = self.get_default_template_handle(primitive_class, bool(is_wireframe))
        return self._templates[handle].copy()

    def get_default_capsule_template(self, is_wireframe: bool) -> PrimitiveAssetAttributes:
        """A copy of the default capsule primitive (solid or wireframe)."""
        return self._default("Capsule3D", is_wireframe)

    def get_default_cone_template(self, is_wireframe: bool) -> PrimitiveAssetAttributes:
        return self._default("Cone", is_wireframe)

    def get_default_cube_template(self, is_wireframe: bool) -> PrimitiveAssetAttributes:
        return self._default("Cube", is_wireframe)

    def get_default_cylinder_template(self, is_wireframe: bool) -> PrimitiveAssetAttributes:
        return self._default("Cylinder", is_wireframe)

    def get_default_icosphere_template(self, is_wireframe: bool) -> PrimitiveAssetAttributes:
        return self._default("Icosphere", is_wireframe)

    def get_default_UVsphere_template(self, is_wireframe: bool) -> PrimitiveAssetAttributes:  # noqa: N802
        return self._default("UVSphere", is_wireframe)


def primitive_object_template(handle: str) -> ObjectAttributes:
    """The object template built on primitive asset ``handle``: rendered and collided as that
    primitive, scaled by :data:`PRIMITIVE_OBJECT_SCALE` (Habitat's prim-based templates)."""
    template = ObjectAttributes(handle)
    template.render_asset_handle = handle
    template.collision_asset_handle = handle
    template.scale = [PRIMITIVE_OBJECT_SCALE] * 3
    return template


class ObjectAttributesManager(_AttributesManager[ObjectAttributes]):
    """Object templates: the 12 primitive-based defaults plus those loaded from files."""

    template_class = ObjectAttributes
    config_suffix = ".object_config.json"

    def __init__(self) -> None:
        super().__init__()
        for handle in PRIMITIVE_ASSET_HANDLES:
            self.register_template(primitive_object_template(handle))
            self._undeletable.add(handle)

    def create_template(
        self, handle: str, register_template: bool = True
    ) -> ObjectAttributes | None:
        """Habitat's ``create_template``: an object template for a primitive asset handle
        (``cubeSolid``, ``capsule3DSolid_hemiRings_4_...``; scale 0.1 as the defaults), else
        as :meth:`create_new_template` (a config file, a mesh file, or defaults). Registered
        unless ``register_template`` is False. An invalid primitive handle gives None with a
        warning, as Habitat logs an error and returns no template."""
        if not isinstance(handle, str):
            raise TypeError(f"handle must be a str, got {handle!r}")
        if not is_primitive_handle(handle):
            return self.create_new_template(handle, register_template)
        try:
            parse_primitive_handle(handle)
        except ValueError as error:
            warnings.warn(f"no object template made for {handle!r}: {error}", stacklevel=2)
            return None
        template = primitive_object_template(handle)
        if register_template:
            self.register_template(template)
        return template

    def create_new_template(self, handle: str, register_template: bool = False) -> ObjectAttributes:
        """A new template named ``handle`` (Habitat's ``create_new_template``).

        An existing ``*.object_config.json`` is read; any other existing file (``.glb``,
        ``.obj``, ...) becomes the template's render and collision asset (its full path is the
        handle); anything else gives a template with default values and no asset.
        """
        if not isinstance(handle, str):
            raise TypeError(f"handle must be a str, got {handle!r}")
        path = Path(handle).expanduser()
        if path.is_file() and path.name.endswith(self.config_suffix):
            template = ObjectAttributes.from_json_file(path)
        elif path.is_file():
            path = path.resolve()
            template = ObjectAttributes(str(path))
            template.file_directory = str(path.parent)
            template.render_asset_handle = str(path)
            template.collision_asset_handle = str(path)
        else:
            template = ObjectAttributes(handle)
        if register_template:
            self.register_template(template)
        return template

    def get_synth_template_handles(self, search_str: str = "", contains: bool = True) -> list[str]:
        """Handles of the primitive-based templates."""
        prims = set(PRIMITIVE_ASSET_HANDLES)
        return [h for h in self._matching_handles(search_str, contains) if h in prims]

    def get_file_template_handles(self, search_str: str = "", contains: bool = True) -> list[str]:
        """Handles of the templates loaded from config files."""
        prims = set(PRIMITIVE_ASSET_HANDLES)
        return [h for h in self._matching_handles(search_str, contains) if h not in prims]


class StageAttributesManager(_AttributesManager[StageAttributes]):
    """Stage templates from ``*.stage_config.json`` or a bare render asset."""

    template_class = StageAttributes
    config_suffix = ".stage_config.json"

    def create_template_for_asset(self, asset_path: str | Path) -> StageAttributes:
        """The stage template for ``scene_id``: its config file, the config beside a mesh
        (``<stem>.stage_config.json``), or, for a bare mesh, defaults with a Z-up frame
        (asset ``(x, y, z)`` -> world ``(x, z, -y)``, Habitat's default for a ``.glb`` stage)."""
        given = Path(asset_path).expanduser().absolute()
        path = given.resolve()
        if path.name.endswith(self.config_suffix):
            return StageAttributes.from_json_file(path)
        if not path.is_file():
            raise FileNotFoundError(f"stage asset not found: {path}")
        beside = path.with_name(path.name.split(".")[0] + self.config_suffix)
        if beside.is_file():
            template = StageAttributes.from_json_file(beside)
            if not template.render_asset_handle:
                template.render_asset_handle = str(path)
            template.handle = str(given)  # named after the scene as given (Habitat's handle)
            return template
        # as Habitat, the template keeps the scene path as given (render_asset_fullpath ==
        # scene_id, relative to the working folder when relative)
        as_given = str(Path(asset_path).expanduser())
        template = StageAttributes(as_given)
        template.render_asset_handle = as_given
        template.orient_up = [0.0, 0.0, 1.0]
        template.orient_front = [0.0, 1.0, 0.0]
        return template


class PhysicsAttributesManager(_AttributesManager[PhysicsManagerAttributes]):
    """Physics world settings from ``*.physics_config.json`` (defaults when none given)."""

    template_class = PhysicsManagerAttributes
    config_suffix = ".physics_config.json"

    def load(self, path: str | Path | None = None) -> PhysicsManagerAttributes:
        """Read and register a physics config; ``None`` or ``""`` gives Habitat's defaults."""
        if not path:
            template = PhysicsManagerAttributes("default.physics_config.json")
        else:
            template = PhysicsManagerAttributes.from_json_file(self._config_files(path)[0])
        self.register_template(template)  # -1 when locked: the registered one is returned
        return self._templates[template.handle].copy()
