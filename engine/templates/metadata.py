"""Scene datasets: Habitat's ``MetadataMediator`` as far as the rigid-object workflow needs it.

A scene dataset (``*.scene_dataset_config.json``) gathers the object and stage templates of a
collection of scenes. The mediator keeps one set of template managers per dataset and
switches between them (``set_active_dataset``); the ``"default"`` dataset holds only the
built-in primitives. The simulator uses the active dataset's managers, so
``sim_cfg.scene_dataset_config_file = ".../my.scene_dataset_config.json"`` makes its objects
available by handle, and ``scene_id`` may name one of its stage templates.

What a dataset file may say, per section (``"objects"``, ``"stages"``, ``"scene_instances"``;
other sections such as lights, navmeshes and articulated objects are listed but not loaded;
scene instance files are read when ``scene_id`` names one, :mod:`engine.scene.instance`):

* ``"paths": {".json": [folder, "folder/*", file, ...]}`` (relative to the dataset file):
  every ``*.object_config.json`` / ``*.stage_config.json`` found there (a ``*`` entry means
  each matching folder); ``".glb"`` entries make stage templates of bare meshes;
* ``"default_attributes"``: JSON values every template of the section starts from (a
  template file's own values win);
* ``"configs"``: ``[{"original_file": f, "template_handle": h, "attributes": {...}}]``: a
  copy of file ``f`` with ``attributes`` applied, registered as ``h``; without
  ``original_file``, a new template from ``attributes`` alone (paths relative to the
  dataset file). A missing file is skipped with a warning (Habitat logs).
"""

from __future__ import annotations

import glob
import json
import warnings
from pathlib import Path
from typing import Any

from engine.templates.attributes import ObjectAttributes, StageAttributes, read_json_object
from engine.templates.managers import (
    AssetAttributesManager,
    ObjectAttributesManager,
    PhysicsAttributesManager,
    StageAttributesManager,
)

__all__ = ["DEFAULT_DATASET", "DatasetManagers", "MetadataMediator"]

#: name of the built-in dataset (primitives only), Habitat's ``"default"``
DEFAULT_DATASET = "default"
_SUFFIX = ".scene_dataset_config.json"


class DatasetManagers:
    """The template managers of one dataset, and what its file listed but rigidsim skips."""

    def __init__(self, name: str) -> None:
        self.name = name
        self.object_template_manager = ObjectAttributesManager()
        self.stage_template_manager = StageAttributesManager()
        self.asset_template_manager = AssetAttributesManager()
        self.physics_template_manager = PhysicsAttributesManager()
        self.scene_instance_handles: list[str] = []
        self.skipped_sections: list[str] = []


class MetadataMediator:
    """Habitat's ``habitat_sim.metadata.MetadataMediator`` (see the module docstring)."""

    def __init__(self, sim_cfg: Any = None) -> None:
        self._datasets: dict[str, DatasetManagers] = {
            DEFAULT_DATASET: DatasetManagers(DEFAULT_DATASET)
        }
        self._active = DEFAULT_DATASET
        dataset = getattr(sim_cfg, "scene_dataset_config_file", DEFAULT_DATASET) or DEFAULT_DATASET
        if dataset != DEFAULT_DATASET and not self.set_active_dataset(dataset):
            raise FileNotFoundError(f"scene dataset config not found: {dataset}")

    # -- datasets ------------------------------------------------------------------------------
    @property
    def active_dataset(self) -> str:
        return self._active

    @active_dataset.setter
    def active_dataset(self, name: str) -> None:
        self.set_active_dataset(name)

    def dataset_exists(self, name: str) -> bool:
        return self._key(name) in self._datasets

    def get_dataset_handles(self) -> list[str]:
        return sorted(self._datasets)

    def set_active_dataset(self, name: str) -> bool:
        """Make ``name`` active, loading it first if needed; False (warning) if it is not
        ``"default"`` and no such file exists."""
        key = self._key(name)
        if key not in self._datasets:
            path = Path(key)
            if not path.is_file():
                warnings.warn(f"scene dataset config not found: {name}", stacklevel=2)
                return False
            self._datasets[key] = _load_dataset(path)
        self._active = key
        return True

    def remove_dataset(self, name: str) -> bool:
        """Forget a dataset (not the default one, nor the active one)."""
        key = self._key(name)
        if key in (DEFAULT_DATASET, self._active) or key not in self._datasets:
            return False
        del self._datasets[key]
        return True

    @staticmethod
    def _key(name: str) -> str:
        if name in ("", DEFAULT_DATASET):
            return DEFAULT_DATASET
        path = Path(name).expanduser()
        if not path.name.endswith(_SUFFIX) and path.with_name(path.name + _SUFFIX).is_file():
            path = path.with_name(path.name + _SUFFIX)
        return str(path.resolve())

    # -- the active dataset's managers ------------------------------------------------------
    @property
    def _current(self) -> DatasetManagers:
        return self._datasets[self._active]

    @property
    def object_template_manager(self) -> ObjectAttributesManager:
        return self._current.object_template_manager

    @property
    def stage_template_manager(self) -> StageAttributesManager:
        return self._current.stage_template_manager

    @property
    def asset_template_manager(self) -> AssetAttributesManager:
        return self._current.asset_template_manager

    @property
    def physics_template_manager(self) -> PhysicsAttributesManager:
        return self._current.physics_template_manager

    def get_scene_handles(self) -> list[str]:
        """The scene instance files the active dataset lists (``*.scene_instance.json``)."""
        return list(self._current.scene_instance_handles)

    @property
    def summary(self) -> str:
        current = self._current
        return (
            f"dataset {current.name}: {current.object_template_manager.get_num_templates()} "
            f"object templates, {current.stage_template_manager.get_num_templates()} "
            f"stage templates"
        )

    def dataset_report(self, name: str = "") -> str:
        """One line per dataset section: what was loaded and what rigidsim skipped."""
        dataset = self._datasets[self._key(name) if name else self._active]
        lines = [
            f"{dataset.name}:",
            f"  objects: {dataset.object_template_manager.get_num_templates()}",
            f"  stages: {dataset.stage_template_manager.get_num_templates()}",
            f"  scene instances: {len(dataset.scene_instance_handles)}",
        ]
        if dataset.skipped_sections:
            lines.append(f"  not loaded by rigidsim: {', '.join(dataset.skipped_sections)}")
        return "\n".join(lines)


# -- loading a dataset file ------------------------------------------------------------------------
_SECTIONS = {
    "objects": (ObjectAttributes, ".object_config.json"),
    "stages": (StageAttributes, ".stage_config.json"),
}


def _load_dataset(path: Path) -> DatasetManagers:
    """Read a ``*.scene_dataset_config.json`` into fresh managers (module docstring)."""
    data = read_json_object(path)
    dataset = DatasetManagers(str(path.resolve()))
    root = path.parent
    managers: dict[str, ObjectAttributesManager | StageAttributesManager] = {
        "objects": dataset.object_template_manager,
        "stages": dataset.stage_template_manager,
    }
    for section, (template_class, suffix) in _SECTIONS.items():
        block = data.get(section, {})
        defaults = dict(block.get("default_attributes", {}))
        manager = managers[section]
        for entry in block.get("paths", {}).get(".json", []):
            for config in _config_files(root, entry, suffix):
                _register(manager, template_class, config, {}, defaults, None)
        if section == "stages":
            stages = dataset.stage_template_manager
            for entry in block.get("paths", {}).get(".glb", []):
                for asset in sorted(glob.glob(str(root / entry))):
                    stages.register_template(stages.create_template_for_asset(asset))
        for config in block.get("configs", []):
            _register_config(manager, template_class, root, config, defaults)
    for entry in data.get("scene_instances", {}).get("paths", {}).get(".json", []):
        dataset.scene_instance_handles += [
            str(p) for p in _config_files(root, entry, ".scene_instance.json")
        ]
    dataset.skipped_sections = sorted(set(data) - {"objects", "stages", "scene_instances"})
    return dataset


def _config_files(root: Path, entry: str, suffix: str) -> list[Path]:
    """Config files named by one ``paths`` entry: a folder, a ``*`` pattern, or a file."""
    found: list[Path] = []
    for match in sorted(glob.glob(str(root / entry))):
        candidate = Path(match)
        if candidate.is_dir():
            found += sorted(candidate.glob(f"*{suffix}"))
        elif candidate.name.endswith(suffix):
            found.append(candidate)
    return found


def _register(
    manager, template_class, config_path: Path, attributes: dict, defaults: dict, handle: str | None
) -> None:
    """Build a template from ``defaults``, the file's values, then ``attributes``."""
    data = json.loads(config_path.read_text()) if config_path.is_file() else {}
    template = template_class(handle or str(config_path.resolve()))
    template.file_directory = str(config_path.parent)
    template._apply_json({**defaults, **data, **attributes}, config_path)
    manager.register_template(template)


def _register_config(manager, template_class, root: Path, config: dict, defaults: dict) -> None:
    """One ``configs`` entry: a modified copy of ``original_file``, or a new template."""
    handle = config.get("template_handle")
    attributes = dict(config.get("attributes", {}))
    original = config.get("original_file")
    if original is not None:
        source = root / original
        if not source.is_file():
            warnings.warn(
                f"dataset config: original_file {source} not found, skipped", stacklevel=3
            )
            return
        _register(manager, template_class, source, attributes, defaults, handle)
        return
    if not handle:
        warnings.warn(
            "dataset config without original_file or template_handle, skipped", stacklevel=3
        )
        return
    # a new template: asset paths are relative to the dataset file
    _register(manager, template_class, root / f"{handle}.json", attributes, defaults, handle)
