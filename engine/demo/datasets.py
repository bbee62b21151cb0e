"""The generated demo dataset: an apartment stage and the tutorial's objects.

Habitat's tutorial downloads ``apartment_1`` and the YCB example objects. rigidsim builds
look-alike stand-ins instead (``engine/demo/scene.py``, ``engine/demo/objects.py``) and
writes them once into a cache folder, laid out like Habitat's ``data/`` folder::

    data/
      scene_datasets/demo/apartment.glb                   stage mesh, Y up, meters
      scene_datasets/demo/apartment.stage_config.json     up [0,1,0], front [0,0,-1]
      scene_datasets/demo/apartment.navmesh               the stage's navmesh (navmesh package)
      test_assets/objects/sphere.object_config.json       + sphere.glb
      objects/example_objects/{cheezit,chefcan,largeclamp,banana,mug}.object_config.json
      objects/locobot_merged/locobot_merged.object_config.json                 + .glb
      VERSION                                             dataset version stamp

Where: the ``path`` argument, else ``$RIGIDSIM_DATA_DIR``, else
``~/.cache/rigidsim/<DATASET_VERSION>/``; the function returns ``<that folder>/data``.
Generation is deterministic (the same bytes every time), takes about a second, and is
atomic: files are written into a temporary sibling folder that is renamed into place, so a
crash never leaves half a dataset. A folder whose ``VERSION`` differs is rebuilt; a
``data`` folder without a demo ``VERSION`` stamp is never touched (FileExistsError).
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from collections.abc import Callable
from pathlib import Path

from engine.demo.geometry import Part, write_glb
from engine.demo.objects import (
    banana_object,
    cheezit_object,
    chefcan_object,
    largeclamp_object,
    locobot_object,
    mug_object,
    sphere_object,
)
from engine.demo.scene import apartment_parts

__all__ = ["DATASET_VERSION", "demo_data_path", "write_demo_dataset"]

DATASET_VERSION = "rigidsim-demo-4"
DATA_DIR_ENV = "RIGIDSIM_DATA_DIR"
STAGE_DIR = Path("scene_datasets") / "demo"
STAGE_NAME = "apartment"

# Folder (relative to data/) and builder of every object.
OBJECTS: dict[str, tuple[Path, Callable[[], tuple[list[Part], dict]]]] = {
    "sphere": (Path("test_assets") / "objects", sphere_object),
    "cheezit": (Path("objects") / "example_objects", cheezit_object),
    "chefcan": (Path("objects") / "example_objects", chefcan_object),
    "largeclamp": (Path("objects") / "example_objects", largeclamp_object),
    "banana": (Path("objects") / "example_objects", banana_object),
    "mug": (Path("objects") / "example_objects", mug_object),
    "locobot_merged": (Path("objects") / "locobot_merged", locobot_object),
}

# Stage physics like Habitat's defaults (world friction 0.4, restitution 0.1).
STAGE_CONFIG = {
    "render_asset": f"{STAGE_NAME}.glb",
    "collision_asset": f"{STAGE_NAME}.glb",
    "up": [0.0, 1.0, 0.0],
    "front": [0.0, 0.0, -1.0],
    "scale": [1.0, 1.0, 1.0],
    "units_to_meters": 1.0,
    "margin": 0.03,
    "friction_coefficient": 0.4,
    "restitution_coefficient": 0.1,
}


def demo_data_path(path: str | os.PathLike | None = None) -> Path:
    """Return the demo ``data`` folder, generating it on first use.

    Parameters
    ----------
    path : str, PathLike or None
        Cache folder to hold ``data/``. Default: ``$RIGIDSIM_DATA_DIR``, else
        ``~/.cache/rigidsim/<DATASET_VERSION>``.

    Returns
    -------
    pathlib.Path
        ``<cache folder>/data``, complete and stamped with :data:`DATASET_VERSION`.
    """
    root = _cache_root(path)
    data = root / "data"
    if _is_current(data):
        return data
    if data.exists() and not _is_ours(data):
        raise FileExistsError(
            f"{data} exists but is not a rigidsim demo dataset (no VERSION stamp); "
            "pass another cache folder or remove it"
        )
    root.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=".data-building-", dir=root))
    try:
        write_demo_dataset(staging)
        _swap_into_place(staging, data)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return data


def write_demo_dataset(data: Path) -> None:
    """Write every file of the dataset into the (existing, empty) folder ``data``."""
    stage_dir = data / STAGE_DIR
    stage_dir.mkdir(parents=True)
    stage_glb = stage_dir / f"{STAGE_NAME}.glb"
    write_glb(apartment_parts(), stage_glb)
    stage_config = dict(STAGE_CONFIG)
    navmesh_file = stage_dir / f"{STAGE_NAME}.navmesh"
    _write_navmesh(stage_glb, navmesh_file)
    stage_config["nav_asset"] = navmesh_file.name
    _write_json(stage_dir / f"{STAGE_NAME}.stage_config.json", stage_config)
    for name, (folder, build) in OBJECTS.items():
        parts, config = build()
        (data / folder).mkdir(parents=True, exist_ok=True)
        write_glb(parts, data / folder / config["render_asset"])
        _write_json(data / folder / f"{name}.object_config.json", config)
    (data / "VERSION").write_text(DATASET_VERSION + "\n")


def _write_navmesh(stage_glb: Path, out: Path) -> None:
    """Build the stage's navmesh with ``navmesh.PathFinder`` and save it to ``out``.

    Raises RuntimeError if the build fails or comes out empty. The stage config is Y-up, so
    the stage frame is the world frame here.
    """
    from engine.scene.assets import load_meshes, merge_meshes
    from navmesh import NavMeshSettings, PathFinder

    stage = merge_meshes(load_meshes(stage_glb))
    pathfinder = PathFinder()
    try:
        built = pathfinder.build(stage.vertices, stage.faces, NavMeshSettings())
        saved = built and pathfinder.save_nav_mesh(str(out))
    except Exception as error:
        raise RuntimeError(f"building the navmesh of {stage_glb} failed: {error}") from error
    if not saved:
        raise RuntimeError(f"the navmesh of {stage_glb} came out empty; nothing to save")


def _write_json(path: Path, content: dict) -> None:
    path.write_text(json.dumps(content, indent=2) + "\n")


def _cache_root(path: str | os.PathLike | None) -> Path:
    """The folder that holds ``data/`` (argument, environment, or the user cache)."""
    if path is not None:
        return Path(path).expanduser()
    override = os.environ.get(DATA_DIR_ENV)
    if override:
        return Path(override).expanduser()
    return Path.home() / ".cache" / "rigidsim" / DATASET_VERSION


def _is_current(data: Path) -> bool:
    """True if ``data`` exists and carries this version's stamp."""
    stamp = data / "VERSION"
    return stamp.is_file() and stamp.read_text().strip() == DATASET_VERSION


def _is_ours(data: Path) -> bool:
    """True if ``data`` carries a demo-dataset stamp of any version (safe to replace)."""
    stamp = data / "VERSION"
    return stamp.is_file() and stamp.read_text().startswith(DATASET_VERSION.rsplit("-", 1)[0])


def _swap_into_place(staging: Path, data: Path) -> None:
    """Rename the finished ``staging`` folder to ``data``, replacing a stale one.

    If another process installed a current dataset meanwhile, keep theirs.
    """
    if data.exists():
        if _is_current(data):
            return
        stale = Path(tempfile.mkdtemp(prefix=".data-stale-", dir=data.parent))
        os.replace(data, stale / "data")
        shutil.rmtree(stale, ignore_errors=True)
    try:
        os.replace(staging, data)
    except OSError:
        if not _is_current(data):  # a concurrent writer won the rename with a good copy?
            raise
