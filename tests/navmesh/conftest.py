"""Fixtures for the navmesh tests: box-built test geometry and the shared Habitat scenes.

Geometry is made of axis-aligned boxes (trimesh.creation.box), world frame Y up, meters.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh

from navmesh import NavMeshSettings, PathFinder


def box(lo, hi) -> trimesh.Trimesh:
    """Closed box with corners lo (3,) and hi (3,), meters."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    mesh = trimesh.creation.box(extents=hi - lo)
    mesh.apply_translation((lo + hi) / 2)
    return mesh


def mesh_arrays(*boxes: trimesh.Trimesh) -> tuple[np.ndarray, np.ndarray]:
    merged = trimesh.util.concatenate(list(boxes))
    return np.asarray(merged.vertices, np.float64), np.asarray(merged.faces, np.int64)


def build(*boxes, **settings) -> PathFinder:
    """PathFinder built from boxes with NavMeshSettings defaults overridden by ``settings``."""
    nav_settings = NavMeshSettings()
    for name, value in settings.items():
        setattr(nav_settings, name, value)
    pathfinder = PathFinder()
    assert pathfinder.build(*mesh_arrays(*boxes), nav_settings)
    return pathfinder


def load_scene(path: Path, z_up: bool, scale: float) -> tuple[np.ndarray, np.ndarray]:
    """Vertices/faces of a .glb in the world frame: Z-up assets map (x, y, z) -> (x, z, -y)."""
    mesh = trimesh.load(path, force="scene").to_geometry()
    vertices = np.asarray(mesh.vertices, np.float64) * scale
    if z_up:
        vertices = np.stack([vertices[:, 0], vertices[:, 2], -vertices[:, 1]], axis=1)
    return vertices, np.asarray(mesh.faces, np.int64)


@pytest.fixture
def geometry():
    """Namespace with the box / build helpers."""

    class Geometry:
        pass

    g = Geometry()
    g.box, g.mesh_arrays, g.build = box, mesh_arrays, build
    return g


@pytest.fixture(scope="session")
def simple_room_mesh(test_assets: Path):
    # simple_room.stage_config.json: up (0, 0, 1), front (0, 1, 0), scale 1
    return load_scene(test_assets / "scenes" / "simple_room.glb", z_up=True, scale=1.0)


@pytest.fixture(scope="session")
def simple_room(simple_room_mesh) -> PathFinder:
    pathfinder = PathFinder()
    pathfinder.build(*simple_room_mesh, NavMeshSettings())
    return pathfinder


@pytest.fixture(scope="session")
def stage_floor1(test_assets: Path) -> PathFinder:
    # stage_floor1.stage_config.json: Y up, scale (2, 2, 2)
    vertices, faces = load_scene(test_assets / "scenes" / "stage_floor1.glb", z_up=False, scale=2.0)
    pathfinder = PathFinder()
    pathfinder.build(vertices, faces, NavMeshSettings())
    return pathfinder
