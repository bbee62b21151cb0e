"""Tests for engine.demo.datasets: the generated demo apartment and objects.

Geometry is checked with ray casts (trimesh's pure-Python ray/triangle test) against the
stage exactly as ``engine.scene.assets.load_meshes`` returns it. Positions in the generated
files are float32, so heights are compared to 1e-5 m.
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

import numpy as np
import pytest
import trimesh

import engine.demo.datasets as datasets
from engine.attributes_managers import ObjectAttributesManager, StageAttributesManager
from engine.demo.datasets import DATASET_VERSION, demo_data_path
from engine.scene.assets import load_meshes, merge_meshes, mesh_aabb

FLOAT32_TOL = 1e-5  # meters: float32 storage of positions of a few meters


@pytest.fixture(scope="module")
def data(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return demo_data_path(tmp_path_factory.mktemp("demo_cache"))


@pytest.fixture(scope="module")
def stage(data: Path) -> trimesh.Trimesh:
    merged = merge_meshes(load_meshes(data / "scene_datasets" / "demo" / "apartment.glb"))
    return trimesh.Trimesh(merged.vertices, merged.faces, process=False)


def _hashes(folder: Path) -> dict[str, str]:
    return {
        str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


def _first_hit(mesh: trimesh.Trimesh, origins: np.ndarray, direction) -> np.ndarray:
    """Distance along the unit ``direction`` to the nearest triangle for each origin.

    Moller-Trumbore ray/triangle test, vectorized over all triangles (inf if no hit).
    """
    triangles = mesh.vertices[mesh.faces]  # (F, 3, 3)
    d = np.asarray(direction, dtype=np.float64)
    e1, e2 = triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0]
    p = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, p)  # det = e1 . (d x e2)
    ok = np.abs(det) > 1e-12
    distances = []
    for origin in np.atleast_2d(np.asarray(origins, dtype=np.float64)):
        s = origin - triangles[:, 0]
        u = np.einsum("ij,ij->i", s, p)[ok] / det[ok]  # barycentric u = s . p / det
        q = np.cross(s[ok], e1[ok])
        v = q @ d / det[ok]  # v = d . (s x e1) / det
        t = np.einsum("ij,ij->i", e2[ok], q) / det[ok]  # t = e2 . (s x e1) / det
        hit = (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 1e-9)
        distances.append(t[hit].min() if np.any(hit) else np.inf)
    return np.array(distances)


def _height_below(mesh: trimesh.Trimesh, x: float, z: float, start_y: float = 0.5) -> float:
    """Height of the first surface straight below ``(x, start_y, z)``."""
    return start_y - float(_first_hit(mesh, [[x, start_y, z]], [0.0, -1.0, 0.0])[0])


# ----------------------------------------------------------------------------------------
# Generation: layout, determinism, caching, atomic replacement
# ----------------------------------------------------------------------------------------


def test_dataset_has_habitat_layout(data: Path) -> None:
    assert data.name == "data"
    expected = [
        "scene_datasets/demo/apartment.glb",
        "scene_datasets/demo/apartment.stage_config.json",
        "test_assets/objects/sphere.object_config.json",
        "test_assets/objects/sphere.glb",
        "objects/example_objects/cheezit.object_config.json",
        "objects/example_objects/chefcan.object_config.json",
        "objects/example_objects/largeclamp.object_config.json",
        "objects/example_objects/banana.object_config.json",
        "objects/example_objects/mug.object_config.json",
        "objects/locobot_merged/locobot_merged.object_config.json",
    ]
    for relative in expected:
        assert (data / relative).is_file(), relative
    assert (data / "VERSION").read_text().strip() == DATASET_VERSION
    assert not [p for p in data.parent.iterdir() if p.name.startswith(".data-")]  # no leftovers


def test_generation_is_deterministic_and_env_override_is_used(
    data: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv(datasets.DATA_DIR_ENV, str(tmp_path / "from_env"))
    second = demo_data_path()
    assert second == tmp_path / "from_env" / "data"
    assert _hashes(second) == _hashes(data)  # same bytes, file by file


def test_second_call_reuses_the_dataset(data: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    before = {p: p.stat().st_mtime_ns for p in data.rglob("*") if p.is_file()}

    def fail(_: Path) -> None:
        raise AssertionError("the dataset was rebuilt")

    monkeypatch.setattr(datasets, "write_demo_dataset", fail)
    assert demo_data_path(data.parent) == data
    assert {p: p.stat().st_mtime_ns for p in data.rglob("*") if p.is_file()} == before


def test_stale_or_partial_dataset_is_replaced(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(datasets, "_write_navmesh", lambda stage, out: False)  # keep it fast
    stale = tmp_path / "data"
    stale.mkdir()
    (stale / "VERSION").write_text("rigidsim-demo-0\n")
    (stale / "leftover.txt").write_text("old")
    data = demo_data_path(tmp_path)
    assert (data / "VERSION").read_text().strip() == DATASET_VERSION
    assert not (data / "leftover.txt").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["data"]


def test_foreign_data_folder_is_never_replaced(tmp_path: Path) -> None:
    foreign = tmp_path / "data"
    foreign.mkdir()
    (foreign / "my_thesis.txt").write_text("precious")
    with pytest.raises(FileExistsError, match="not a rigidsim demo dataset"):
        demo_data_path(tmp_path)
    assert (foreign / "my_thesis.txt").read_text() == "precious"


def test_failed_build_leaves_no_partial_dataset(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def crash(stage: Path, out: Path) -> bool:
        raise RuntimeError("simulated crash while building")

    monkeypatch.setattr(datasets, "_write_navmesh", crash)
    with pytest.raises(RuntimeError, match="simulated crash"):
        demo_data_path(tmp_path)
    assert list(tmp_path.iterdir()) == []  # neither data/ nor a half-built temp folder


# ----------------------------------------------------------------------------------------
# Configs and meshes
# ----------------------------------------------------------------------------------------


def _object_configs(data: Path) -> list[Path]:
    return sorted(data.rglob("*.object_config.json"))


def test_every_config_is_json_and_its_meshes_load(data: Path) -> None:
    configs = _object_configs(data)
    assert len(configs) == 7
    for path in configs:
        config = json.loads(path.read_text())
        assert {"render_asset", "mass"} <= set(config)
        assert config["mass"] > 0
        for key in ("render_asset", "collision_asset"):
            if key in config:
                meshes = load_meshes(path.parent / config[key])
                assert meshes and all(len(m.faces) for m in meshes)
    stage_config_path = data / "scene_datasets" / "demo" / "apartment.stage_config.json"
    stage_config = json.loads(stage_config_path.read_text())
    assert stage_config["up"] == [0.0, 1.0, 0.0] and stage_config["front"] == [0.0, 0.0, -1.0]
    assert stage_config["friction_coefficient"] == 0.4
    assert stage_config["restitution_coefficient"] == 0.1
    assert (stage_config_path.parent / stage_config["render_asset"]).is_file()
    if "nav_asset" in stage_config:
        assert (stage_config_path.parent / stage_config["nav_asset"]).is_file()


def test_configs_load_as_habitat_templates(data: Path) -> None:
    manager = ObjectAttributesManager()
    ids = manager.load_configs(data / "objects" / "example_objects")
    assert len(ids) == 5  # cheezit, chefcan, largeclamp, banana, mug
    (handle,) = manager.get_template_handles("objects/example_objects/cheezit")
    assert manager.get_template_by_handle(handle).mass == pytest.approx(0.411)
    (robot_id,) = manager.load_configs(data / "objects" / "locobot_merged")
    robot = manager.get_template_by_id(robot_id)
    assert not robot.compute_COM_from_shape  # COM given: the bottom of the base
    np.testing.assert_array_equal(np.asarray(robot.com), [0.0, 0.0, 0.0])
    stage = StageAttributesManager().load_configs(data / "scene_datasets" / "demo")
    assert len(stage) == 1


def test_object_sizes(data: Path) -> None:
    examples = data / "objects" / "example_objects"
    box = mesh_aabb(load_meshes(examples / "cheezit.glb"))
    np.testing.assert_allclose(box[1] - box[0], [0.16, 0.06, 0.21], atol=FLOAT32_TOL)
    (cereal,) = load_meshes(examples / "cheezit.glb")
    assert cereal.texture is not None and cereal.uvs is not None  # printed look
    assert len(np.unique(cereal.texture.reshape(-1, 4), axis=0)) >= 4  # several print colors
    can = mesh_aabb(load_meshes(examples / "chefcan.glb"))
    np.testing.assert_allclose(can[1] - can[0], [0.102, 0.102, 0.14], atol=1e-3)  # 32-gon
    sphere = np.concatenate([m.vertices for m in load_meshes(
        data / "test_assets" / "objects" / "sphere.glb")])  # fmt: skip
    np.testing.assert_allclose(np.linalg.norm(sphere, axis=1), 0.25, atol=FLOAT32_TOL)
    banana = mesh_aabb(load_meshes(examples / "banana.glb"))
    assert 0.15 < (banana[1] - banana[0])[0] < 0.2 and (banana[1] - banana[0])[2] < 0.04
    mug = load_meshes(examples / "mug.glb")
    assert len(mug) == 2  # cup and handle: two collision hulls
    np.testing.assert_allclose(mesh_aabb(mug)[:, 2], [-0.04, 0.04], atol=1e-3)
    robot = mesh_aabb(load_meshes(data / "objects" / "locobot_merged" / "locobot_merged.glb"))
    size = robot[1] - robot[0]
    assert 0.33 <= size[0] <= 0.37 and 0.33 <= size[2] <= 0.37  # about 0.35 m across
    np.testing.assert_allclose(robot[0, 1], 0.0, atol=FLOAT32_TOL)  # wheels touch y = 0
    assert 0.5 <= robot[1, 1] < 0.6  # below the tutorial's camera at 0.6 m
    np.testing.assert_allclose(0.5 * (robot[0] + robot[1])[[0, 2]], 0.0, atol=0.01)


# ----------------------------------------------------------------------------------------
# The apartment matches the tutorial's coordinates
# ----------------------------------------------------------------------------------------


def test_floor_is_at_minus_1_45(stage: trimesh.Trimesh) -> None:
    for x, z in [(1.75, 0.4), (0.0, -1.0), (4.5, -3.0), (6.0, 1.5), (5.05, 1.6)]:
        np.testing.assert_allclose(_height_below(stage, x, z), -1.45, atol=FLOAT32_TOL)


def test_coffee_table_top_is_near_minus_1_05_under_the_drops(stage: trimesh.Trimesh) -> None:
    np.testing.assert_allclose(_height_below(stage, 2.45, 0.1), -1.05, atol=FLOAT32_TOL)
    # The tutorial drops a sphere at (2.5, 0.2) and cans/boxes at x = 2.39..2.4, z +-0.28.
    for x, z in [(2.5, 0.2), (2.39, -0.22), (2.39, 0.22), (2.4, -0.28), (2.4, 0.28)]:
        np.testing.assert_allclose(_height_below(stage, x, z), -1.05, atol=FLOAT32_TOL)


def test_floor_is_clear_within_1_m_of_the_robot_start(stage: trimesh.Trimesh) -> None:
    angles = np.linspace(0.0, 2.0 * np.pi, 24, endpoint=False)
    points = [(1.75, 0.4)] + [
        (1.75 + r * np.cos(a), 0.4 + r * np.sin(a)) for r in (0.3, 0.6, 1.0) for a in angles
    ]
    on_table = 0
    for x, z in points:
        if 2.2 <= x <= 2.9 and -0.45 <= z <= 0.55:  # the coffee table may be within 1 m
            on_table += 1
            continue
        # Nothing between 1 m above the ceiling-free space and the floor.
        np.testing.assert_allclose(_height_below(stage, x, z, 1.0), -1.45, atol=FLOAT32_TOL)
    assert on_table < len(points) // 4


def test_ceiling_doorway_and_steps(stage: trimesh.Trimesh) -> None:
    up = _first_hit(stage, [[1.75, 0.0, 0.4]], [0.0, 1.0, 0.0])[0]
    np.testing.assert_allclose(up, 1.3, atol=FLOAT32_TOL)  # ceiling at y = 1.3
    through_door = _first_hit(stage, [[4.0, -0.5, 1.65]], [1.0, 0.0, 0.0])[0]
    np.testing.assert_allclose(through_door, 8.5 - 4.0, atol=FLOAT32_TOL)  # to the end wall
    into_wall = _first_hit(stage, [[4.7, -0.5, 0.0]], [1.0, 0.0, 0.0])[0]
    np.testing.assert_allclose(into_wall, 5.0 - 4.7, atol=FLOAT32_TOL)
    np.testing.assert_allclose(_height_below(stage, 7.3, 0.5), -1.30, atol=FLOAT32_TOL)
    np.testing.assert_allclose(_height_below(stage, 7.9, 0.5), -1.15, atol=FLOAT32_TOL)


def test_tutorial_cameras_see_the_coffee_table(stage: trimesh.Trimesh) -> None:
    table_center = np.array([2.55, -1.05, 0.05])
    for camera_height in (0.6, 1.5):  # the tutorial's sensor offset, and Habitat's default
        eye = np.array([-0.15, -0.7 + camera_height, 1.0])
        direction = (table_center - eye) / np.linalg.norm(table_center - eye)
        hit = _first_hit(stage, [eye], direction)[0]
        np.testing.assert_allclose(hit, np.linalg.norm(table_center - eye), atol=1e-3)


def test_stage_is_textured_and_small(data: Path) -> None:
    meshes = load_meshes(data / "scene_datasets" / "demo" / "apartment.glb")
    floor = [m for m in meshes if m.name == "floor"]
    assert floor and floor[0].texture is not None
    assert floor[0].uvs.min() >= 0.0 and floor[0].uvs.max() <= 1.0
    n_triangles = sum(len(m.faces) for m in meshes)
    assert 1000 <= n_triangles <= 30000
    assert all(m.vertex_colors is not None or m.texture is not None for m in meshes)


def test_navmesh_marks_the_robot_start_walkable(data: Path) -> None:
    navmesh_file = data / "scene_datasets" / "demo" / "apartment.navmesh"
    assert navmesh_file.exists()  # the dataset always builds the stage navmesh
    from navmesh import PathFinder

    pathfinder = PathFinder()
    assert pathfinder.load_nav_mesh(navmesh_file)
    assert pathfinder.is_navigable(np.array([1.75, -1.45, 0.4]))
    assert not pathfinder.is_navigable(np.array([2.55, -1.45, 0.05]))  # under the table
    assert os.path.getsize(navmesh_file) > 0
