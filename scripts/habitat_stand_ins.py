"""The data folder of ``habitat_programs.py``: Habitat's data layout served by stand-ins.

Habitat's programs open fixed paths (``data/scene_datasets/habitat-test-scenes/...``); this
module builds ``<work>/data`` with those paths, pointing at rigidsim's demo data and at
Habitat's MIT test assets:

- ``habitat-test-scenes/skokloster-castle``: the demo apartment **moved** so that the goal
  Habitat's ``examples/settings.py`` hard-codes (``goal_position``, on the castle's floor)
  lies on the apartment's largest navmesh island: ``example.py --compute_action_shortest_path``
  asks the greedy follower for a path to it and fails when there is none. The moved copy is
  the same ``.glb`` with one parent node carrying the offset, the same stage config and the
  same navmesh, shifted by that offset;
- ``habitat-test-scenes/{van-gogh-room,apartment_1}`` and the mp3d example house: links to
  the demo apartment;
- ``mp3d_example/mp3d.scene_dataset_config.json``: a generated dataset config whose only stage
  template is the demo apartment's (no semantic annotations: the semantic scene is empty);
- ``replica_cad/``: a generated ReplicaCAD-like scene dataset (``replicaCAD.scene_dataset_config
  .json``, ``configs/{stages,objects,scenes}``) for the coordinate frame tutorial: the demo
  apartment as ``frl_apartment_stage``, demo objects under ReplicaCAD's names
  (``frl_apartment_chair_01`` is the cracker box, scaled 3x) and a scene instance
  ``v3_sc0_staging_00`` placing four of them;
- ``objects/``: rigidsim's demo objects; ``test_assets``: Habitat's test assets plus the demo's
  ``test_assets`` files they lack.
"""

from __future__ import annotations

import dataclasses
import json
import shutil
import struct
from pathlib import Path

import numpy as np

from navmesh.navmesh_data import NavMeshData

#: Habitat's scene paths (without suffix) -> the demo scene linked there (.glb and .navmesh)
LINKED_SCENES = {
    "scene_datasets/habitat-test-scenes/van-gogh-room": "scene_datasets/demo/apartment",
    "scene_datasets/habitat-test-scenes/apartment_1": "scene_datasets/demo/apartment",
    "scene_datasets/mp3d_example/17DRP5sb8fy/17DRP5sb8fy": "scene_datasets/demo/apartment",
}
#: Habitat's scene path -> (demo scene, the Habitat position that must land on its navmesh)
MOVED_SCENES = {
    "scene_datasets/habitat-test-scenes/skokloster-castle": (
        "scene_datasets/demo/apartment",
        (5.047, 0.199, 11.145),  # examples/settings.py: example_settings["goal_position"]
    ),
}
#: scene dataset configs Habitat's programs name, generated: (path under data/, JSON content)
GENERATED_CONFIGS = (
    # the mp3d example dataset: its one stage, the demo apartment linked above
    (
        "scene_datasets/mp3d_example/mp3d.scene_dataset_config.json",
        {"stages": {"paths": {".json": ["../demo"]}}, "objects": {"paths": {".json": []}}},
    ),
)
# ReplicaCAD (the coordinate frame tutorial): a scene dataset of the same layout, generated
_REPLICA = "replica_cad"
_REPLICA_OBJECTS = {  # stand-in object name -> (demo asset, scale, mass kg)
    "frl_apartment_chair_01": ("objects/example_objects/cheezit.glb", 3.0, 5.0),
    "frl_apartment_bowl_07": ("objects/example_objects/chefcan.glb", 1.0, 0.4),
    "frl_apartment_kitchen_utensil_01": ("objects/example_objects/banana.glb", 1.0, 0.1),
}
GENERATED_LINKS = (  # (path under data/, path in the demo data)
    (f"{_REPLICA}/stages/frl_apartment_stage.glb", "scene_datasets/demo/apartment.glb"),
    (f"{_REPLICA}/stages/frl_apartment_stage.navmesh", "scene_datasets/demo/apartment.navmesh"),
    *(
        (f"{_REPLICA}/objects/{name}.glb", asset)
        for name, (asset, _, _) in _REPLICA_OBJECTS.items()
    ),
)
GENERATED_CONFIGS += (
    (
        f"{_REPLICA}/replicaCAD.scene_dataset_config.json",
        {
            "stages": {"paths": {".json": ["configs/stages"]}},
            "objects": {"paths": {".json": ["configs/objects"]}},
            "scene_instances": {"paths": {".json": ["configs/scenes"]}},
        },
    ),
    (
        f"{_REPLICA}/configs/stages/frl_apartment_stage.stage_config.json",
        {"render_asset": "../../stages/frl_apartment_stage.glb", "up": [0, 1, 0],
         "front": [0, 0, -1], "nav_asset": "../../stages/frl_apartment_stage.navmesh"},
    ),
    *(
        (
            f"{_REPLICA}/configs/objects/{name}.object_config.json",
            {"render_asset": f"../../objects/{name}.glb", "scale": [scale] * 3, "mass": mass},
        )
        for name, (_, scale, mass) in _REPLICA_OBJECTS.items()
    ),
    (  # the demo apartment's floor is at y = -1.45 m
        f"{_REPLICA}/configs/scenes/v3_sc0_staging_00.scene_instance.json",
        {
            "translation_origin": "asset_local",
            "stage_instance": {"template_name": "stages/frl_apartment_stage"},
            "object_instances": [
                {"template_name": "objects/frl_apartment_chair_01", "motion_type": "DYNAMIC",
                 "translation": [1.5, -1.13, -0.5], "rotation": [0.924, 0, 0.383, 0]},
                {"template_name": "objects/frl_apartment_chair_01", "motion_type": "DYNAMIC",
                 "translation": [0.5, -1.13, 1.5], "rotation": [1, 0, 0, 0]},
                {"template_name": "objects/frl_apartment_bowl_07", "motion_type": "STATIC",
                 "translation": [2.0, -0.82, -1.0], "rotation": [1, 0, 0, 0]},
                {"template_name": "objects/frl_apartment_kitchen_utensil_01",
                 "motion_type": "DYNAMIC", "translation": [2.2, -0.86, -1.1],
                 "rotation": [0.707, 0, 0.707, 0]},
            ],
        },
    ),
)  # fmt: skip
GLB_HEADER = struct.Struct("<4sII")  # magic, version, total length
GLB_CHUNK = struct.Struct("<I4s")  # chunk length, chunk type


def link_data(work: Path, demo: Path, assets: Path) -> None:
    """Build ``work/data``: Habitat's data layout as links to the demo data and the test assets."""
    data = work / "data"
    for sub in ("objects", "scene_datasets/demo"):
        (data / sub).parent.mkdir(parents=True, exist_ok=True)
        (data / sub).symlink_to(demo / sub, target_is_directory=True)
    link_test_assets(data / "test_assets", assets / "test_assets", demo / "test_assets")
    for config in assets.glob("*.json"):
        (data / config.name).symlink_to(config)
    for habitat_name, stand_in in LINKED_SCENES.items():
        for suffix in (".glb", ".navmesh"):
            link = data / (habitat_name + suffix)
            link.parent.mkdir(parents=True, exist_ok=True)
            link.symlink_to((demo / stand_in).with_suffix(suffix))
    for habitat_name, (stand_in, goal) in MOVED_SCENES.items():
        write_moved_scene(demo / stand_in, data / habitat_name, np.asarray(goal, dtype=float))
    for relative, target in GENERATED_LINKS:
        (data / relative).parent.mkdir(parents=True, exist_ok=True)
        (data / relative).symlink_to(demo / target)
    for relative, content in GENERATED_CONFIGS:
        (data / relative).parent.mkdir(parents=True, exist_ok=True)
        (data / relative).write_text(json.dumps(content, indent=2) + "\n", encoding="utf-8")


def link_test_assets(target: Path, habitat_assets: Path, demo_assets: Path) -> None:
    """Copy Habitat's test assets (as links) to ``target``; link the demo's files they lack."""
    shutil.copytree(habitat_assets, target, symlinks=True)
    for extra in demo_assets.rglob("*"):
        destination = target / extra.relative_to(demo_assets)
        if extra.is_file() and not destination.exists():
            destination.parent.mkdir(parents=True, exist_ok=True)
            destination.symlink_to(extra)


def write_moved_scene(source: Path, target: Path, goal: np.ndarray) -> np.ndarray:
    """Write ``target``'s .glb, .stage_config.json and .navmesh: ``source`` moved so that
    ``goal`` is on its largest island; return the offset (m)."""
    navmesh = NavMeshData.load(source.with_suffix(".navmesh"))
    offset = goal - central_island_point(navmesh)
    target.parent.mkdir(parents=True, exist_ok=True)
    write_moved_glb(source.with_suffix(".glb"), target.with_suffix(".glb"), offset)
    moved_navmesh(navmesh, offset).save(target.with_suffix(".navmesh"))
    config = json.loads(source.with_suffix(".stage_config.json").read_text(encoding="utf-8"))
    for key, suffix in (
        ("render_asset", ".glb"),
        ("collision_asset", ".glb"),
        ("nav_asset", ".navmesh"),
    ):
        if key in config:
            config[key] = target.with_suffix(suffix).name
    target.with_suffix(".stage_config.json").write_text(json.dumps(config, indent=2) + "\n")
    return offset


def central_island_point(navmesh: NavMeshData) -> np.ndarray:
    """The centre (world x, floor y, z) of the largest island's cell nearest its centroid."""
    layer, row, column = np.nonzero(navmesh.island == 0)
    x = navmesh.origin_xz[0] + (column + 0.5) * navmesh.cell_size
    z = navmesh.origin_xz[1] + (row + 0.5) * navmesh.cell_size
    nearest = int(np.argmin((x - x.mean()) ** 2 + (z - z.mean()) ** 2))
    floor = navmesh.floor[layer[nearest], row[nearest], column[nearest]]
    return np.array([x[nearest], floor, z[nearest]])


def moved_navmesh(navmesh: NavMeshData, offset: np.ndarray) -> NavMeshData:
    """``navmesh`` translated by ``offset`` (bounds, grid origin, floor and ceiling heights)."""
    return dataclasses.replace(
        navmesh,
        bounds=navmesh.bounds + offset,
        origin_xz=navmesh.origin_xz + offset[[0, 2]],
        floor=navmesh.floor + offset[1],
        ceiling=navmesh.ceiling + offset[1],
    )


def write_moved_glb(source: Path, target: Path, offset: np.ndarray) -> None:
    """Copy the binary glTF ``source`` to ``target`` with its scene under one new parent node
    translated by ``offset`` (the meshes, materials and buffers are the same bytes)."""
    blob = source.read_bytes()
    magic, version, _ = GLB_HEADER.unpack_from(blob, 0)
    json_length, json_type = GLB_CHUNK.unpack_from(blob, GLB_HEADER.size)
    if magic != b"glTF" or json_type != b"JSON":
        raise ValueError(f"{source} is not a binary glTF file")
    start = GLB_HEADER.size + GLB_CHUNK.size
    gltf = json.loads(blob[start : start + json_length])
    scene = gltf["scenes"][gltf.get("scene", 0)]
    gltf["nodes"].append(
        {"name": "stand_in_offset", "translation": offset.tolist(), "children": scene["nodes"]}
    )
    scene["nodes"] = [len(gltf["nodes"]) - 1]
    text = json.dumps(gltf, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)  # chunks are 4-byte aligned, JSON padded with spaces
    rest = blob[start + json_length :]
    body = GLB_CHUNK.pack(len(text), b"JSON") + text + rest
    target.write_bytes(GLB_HEADER.pack(magic, version, GLB_HEADER.size + len(body)) + body)
