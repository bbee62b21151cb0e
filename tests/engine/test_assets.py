"""Tests for engine.scene.assets and engine.scene.primitives: Habitat assets, unit primitives."""

from __future__ import annotations

import json
import os
import shutil
import struct
from pathlib import Path

import numpy as np
import pytest
import trimesh

from engine.scene.assets import (
    PRIMITIVE_ASSET_HANDLES,
    MeshData,
    clear_mesh_cache,
    frame_rotation,
    load_meshes,
    merge_meshes,
    mesh_aabb,
    primitive_meshes,
)
from engine.scene.primitives import is_primitive_handle, parse_primitive_handle

# Loading and transforming float64 data: only rounding error (positions are O(10) m).
POSITION_TOL = 1e-9


def _all_asset_files(test_assets: Path) -> list[Path]:
    files = []
    for pattern in ("**/*.glb", "**/*.ply"):
        files += sorted(test_assets.glob(pattern))
    return files


def _check_mesh_arrays(mesh: MeshData) -> None:
    assert mesh.vertices.dtype == np.float64 and mesh.vertices.shape[1] == 3
    assert mesh.faces.dtype == np.int64 and mesh.faces.shape[1] == 3
    assert len(mesh.faces) > 0
    assert np.all(np.isfinite(mesh.vertices))
    assert mesh.faces.min() >= 0 and mesh.faces.max() < len(mesh.vertices)
    assert mesh.base_color.dtype == np.uint8 and mesh.base_color.shape == (4,)
    if mesh.vertex_colors is not None:
        assert mesh.vertex_colors.shape == (len(mesh.vertices), 4)
        assert mesh.vertex_colors.dtype == np.uint8
    if mesh.texture is not None:
        assert mesh.uvs is not None and mesh.uvs.shape == (len(mesh.vertices), 2)
        assert mesh.uvs.dtype == np.float32
        assert mesh.texture.dtype == np.uint8 and mesh.texture.ndim == 3
        assert mesh.texture.shape[2] == 4


def test_every_real_habitat_asset_loads(test_assets: Path) -> None:
    files = _all_asset_files(test_assets)
    assert len(files) >= 15  # objects, scenes, dataset_tests
    for path in files:
        meshes = load_meshes(path)
        assert meshes, path
        for mesh in meshes:
            _check_mesh_arrays(mesh)


def test_transform_box_node_transforms_place_six_faces_on_unit_cube(test_assets: Path) -> None:
    meshes = load_meshes(test_assets / "objects" / "transform_box.glb")
    assert len(meshes) == 6
    np.testing.assert_allclose(mesh_aabb(meshes), [[-1, -1, -1], [1, 1, 1]], atol=1e-6)
    # Each plane lies flat on one distinct face of the cube (|coordinate| == 1 on one axis).
    sides = set()
    for mesh in meshes:
        spans = np.ptp(mesh.vertices, axis=0)
        axis = int(np.argmin(spans))
        assert spans[axis] < 1e-6
        value = float(mesh.vertices[0, axis])
        np.testing.assert_allclose(abs(value), 1.0, atol=1e-6)
        sides.add((axis, np.sign(value)))
    assert len(sides) == 6
    # The file stores the planes with node transforms, so applying them is what matters.
    scene = trimesh.load(test_assets / "objects" / "transform_box.glb", force="scene")
    node_transforms = [scene.graph[node][0] for node in scene.graph.nodes_geometry]
    assert any(not np.allclose(t, np.eye(4)) for t in node_transforms)


def test_nested_box_has_two_meshes_and_five_boxes_five(test_assets: Path) -> None:
    assert len(load_meshes(test_assets / "objects" / "nested_box.glb")) == 2
    boxes = load_meshes(test_assets / "objects" / "5boxes.glb")
    assert len(boxes) == 5
    centers = np.array([m.vertices.mean(axis=0) for m in boxes])
    assert len(np.unique(np.round(centers, 3), axis=0)) == 5  # five distinct placements


def test_skinned_prism_and_sphere_sizes(test_assets: Path) -> None:
    prism = load_meshes(test_assets / "objects" / "skinned_prism.glb")
    np.testing.assert_allclose(mesh_aabb(prism), [[-1, 0, -1], [1, 6, 1]], atol=1e-4)
    sphere = load_meshes(test_assets / "objects" / "sphere.glb")
    radii = np.linalg.norm(np.concatenate([m.vertices for m in sphere]), axis=1)
    np.testing.assert_allclose(radii, 0.25, rtol=1e-4)  # float32 positions in the file
    assert tuple(sphere[0].base_color[:3]) == (204, 1, 1)  # red material factor


def _raw_glb_texcoords(path: Path) -> np.ndarray:
    """Read TEXCOORD_0 of the first primitive straight from the GLB binary chunk."""
    data = path.read_bytes()
    json_length = struct.unpack("<I", data[12:16])[0]
    document = json.loads(data[20 : 20 + json_length])
    binary_start = 20 + json_length + 8
    accessor_index = document["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"]
    accessor = document["accessors"][accessor_index]
    view = document["bufferViews"][accessor["bufferView"]]
    start = binary_start + view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
    count = accessor["count"]
    return np.frombuffer(data[start : start + 8 * count], dtype="<f4").reshape(count, 2)


def test_chair_is_textured_with_opengl_uv_convention(test_assets: Path) -> None:
    path = test_assets / "objects" / "chair.glb"
    (chair,) = load_meshes(path)
    assert chair.texture is not None and chair.texture.shape == (1024, 1024, 4)
    assert chair.uvs is not None and chair.uvs.shape == (len(chair.vertices), 2)
    raw = _raw_glb_texcoords(path)  # glTF: v = 0 at the top row of the image
    np.testing.assert_allclose(chair.uvs[:, 0], raw[:, 0], atol=1e-6)
    np.testing.assert_allclose(chair.uvs[:, 1], 1.0 - raw[:, 1], atol=1e-6)  # documented flip


def test_simple_room_z_up_maps_x_y_z_to_x_z_minus_y(test_assets: Path) -> None:
    path = test_assets / "scenes" / "simple_room.glb"
    raw = load_meshes(path)
    converted = load_meshes(path, up=(0, 0, 1), front=(0, 1, 0))
    for a, b in zip(raw, converted, strict=True):
        expected = np.stack([a.vertices[:, 0], a.vertices[:, 2], -a.vertices[:, 1]], axis=1)
        np.testing.assert_allclose(b.vertices, expected, atol=POSITION_TOL)
        np.testing.assert_array_equal(a.faces, b.faces)  # a rotation keeps the winding


def test_scale_and_units_apply_after_rotation(test_assets: Path) -> None:
    path = test_assets / "objects" / "nested_box.glb"
    raw = load_meshes(path)
    scaled = load_meshes(path, scale=(2.0, 3.0, 4.0), units_to_meters=0.5)
    for a, b in zip(raw, scaled, strict=True):
        np.testing.assert_allclose(b.vertices, a.vertices * [1.0, 1.5, 2.0], atol=POSITION_TOL)
    # Z-up plus scale: the scale acts on the converted (Y-up) axes.
    rotated = load_meshes(path, up=(0, 0, 1), front=(0, 1, 0), scale=(1.0, 2.0, 1.0))
    for a, b in zip(raw, rotated, strict=True):
        expected = np.stack([a.vertices[:, 0], 2.0 * a.vertices[:, 2], -a.vertices[:, 1]], 1)
        np.testing.assert_allclose(b.vertices, expected, atol=POSITION_TOL)


def test_frame_rotation_is_proper_and_maps_up_and_front() -> None:
    rng = np.random.default_rng(3)
    for _ in range(20):
        up = rng.normal(size=3)
        front = np.cross(up, rng.normal(size=3))
        rotation = frame_rotation(up, front)
        np.testing.assert_allclose(rotation @ rotation.T, np.eye(3), atol=1e-12)
        np.testing.assert_allclose(np.linalg.det(rotation), 1.0, atol=1e-12)
        np.testing.assert_allclose(rotation @ (up / np.linalg.norm(up)), [0, 1, 0], atol=1e-12)
        unit_front = front / np.linalg.norm(front)
        np.testing.assert_allclose(rotation @ unit_front, [0, 0, -1], atol=1e-12)
    np.testing.assert_allclose(frame_rotation((0, 1, 0), (0, 0, -1)), np.eye(3))


def test_bad_inputs_raise_clear_errors(tmp_path: Path, test_assets: Path) -> None:
    box = test_assets / "objects" / "nested_box.glb"
    with pytest.raises(FileNotFoundError, match="missing.glb"):
        load_meshes(tmp_path / "missing.glb")
    with pytest.raises(ValueError, match="orthogonal"):
        load_meshes(box, up=(0, 1, 0), front=(0, 1, 1))
    with pytest.raises(ValueError, match="up"):
        load_meshes(box, up=(0, 0, 0))
    with pytest.raises(ValueError, match="front"):
        load_meshes(box, front=(0, np.nan, -1))
    with pytest.raises(ValueError, match="scale"):
        load_meshes(box, scale=(1, -1, 1))
    with pytest.raises(ValueError, match="units_to_meters"):
        load_meshes(box, units_to_meters=0.0)
    garbage = tmp_path / "garbage.glb"
    garbage.write_bytes(b"this is not a glb file at all")
    with pytest.raises(ValueError, match="garbage.glb"):
        load_meshes(garbage)
    points_only = tmp_path / "points_only.obj"
    points_only.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\n")
    with pytest.raises(ValueError, match="points_only.obj"):
        load_meshes(points_only)
    text = tmp_path / "notes.txt"
    text.write_text("hello")
    with pytest.raises(ValueError, match="notes.txt"):
        load_meshes(text)


def test_cache_shares_read_only_arrays_and_notices_file_changes(
    tmp_path: Path, test_assets: Path
) -> None:
    clear_mesh_cache()
    path = tmp_path / "asset.glb"
    shutil.copy(test_assets / "objects" / "nested_box.glb", path)
    first = load_meshes(path)
    second = load_meshes(path)
    assert first[0].vertices is second[0].vertices  # served from the cache
    assert first[0] is not second[0]  # but each call gets its own MeshData objects
    with pytest.raises(ValueError):
        first[0].vertices[0, 0] = 5.0  # read-only: the cache cannot be corrupted
    editable = first[0].copy()
    editable.vertices[0, 0] = 5.0  # copies are writable
    assert second[0].vertices[0, 0] != 5.0
    # Replace the file with a different asset: new mtime/size -> reloaded.
    shutil.copy(test_assets / "objects" / "transform_box.glb", path)
    os.utime(path, ns=(1, 1))
    assert len(load_meshes(path)) == 6


def test_obj_with_face_colors_and_vertex_colors_load(tmp_path: Path) -> None:
    box = trimesh.creation.box(extents=(1.0, 2.0, 3.0))
    box.visual.face_colors = np.tile([10, 200, 30, 255], (len(box.faces), 1))
    path = tmp_path / "colored.ply"
    box.export(path)
    (mesh,) = load_meshes(path)
    assert mesh.vertex_colors is not None
    np.testing.assert_array_equal(np.unique(mesh.vertex_colors, axis=0), [[10, 200, 30, 255]])
    np.testing.assert_allclose(mesh_aabb(mesh), [[-0.5, -1, -1.5], [0.5, 1, 1.5]])


def test_merge_meshes_concatenates_and_keeps_colors(test_assets: Path) -> None:
    parts = load_meshes(test_assets / "objects" / "transform_box.glb")
    merged = merge_meshes(parts)
    assert len(merged.vertices) == sum(len(p.vertices) for p in parts)
    assert len(merged.faces) == sum(len(p.faces) for p in parts)
    last = parts[-1]
    np.testing.assert_allclose(merged.vertices[merged.faces[-1]], last.vertices[last.faces[-1]])
    assert merged.vertex_colors is not None and merged.vertex_colors.shape == (24, 4)
    np.testing.assert_array_equal(merged.vertex_colors[0], parts[0].base_color)
    np.testing.assert_allclose(mesh_aabb(merged), mesh_aabb(parts))
    with pytest.raises(ValueError):
        merge_meshes([])
    with pytest.raises(ValueError):
        mesh_aabb([])


# ----------------------------------------------------------------------------------------
# Primitives
# ----------------------------------------------------------------------------------------


def test_there_are_twelve_sorted_primitive_handles() -> None:
    assert len(PRIMITIVE_ASSET_HANDLES) == 12
    assert PRIMITIVE_ASSET_HANDLES == sorted(PRIMITIVE_ASSET_HANDLES)
    assert "cubeSolid" in PRIMITIVE_ASSET_HANDLES
    assert "icosphereSolid_subdivs_1" in PRIMITIVE_ASSET_HANDLES
    assert (
        "cylinderSolid_rings_1_segments_12_halfLen_1_useTexCoords_false_useTangents_false"
        "_capEnds_true" in PRIMITIVE_ASSET_HANDLES
    )
    assert all(is_primitive_handle(h) for h in PRIMITIVE_ASSET_HANDLES)
    assert not is_primitive_handle("chair.glb")


def _volume(mesh: MeshData) -> float:
    return float(trimesh.Trimesh(mesh.vertices, mesh.faces, process=False).volume)


def test_every_primitive_is_closed_outward_and_unit_sized() -> None:
    for handle in PRIMITIVE_ASSET_HANDLES:
        (mesh,) = primitive_meshes(handle)
        _check_mesh_arrays(mesh)
        welded = trimesh.Trimesh(mesh.vertices, mesh.faces)  # merges duplicated seam vertices
        assert welded.is_watertight, handle
        assert _volume(mesh) > 0.0, handle  # counter-clockwise from outside
        kind, params = parse_primitive_handle(handle)
        half_height = {
            "capsule": params.get("halfLen", 0.0) + 1.0,
            "cone": params.get("halfLen", 0.0),
            "cylinder": params.get("halfLen", 0.0),
        }.get(kind, 1.0)
        np.testing.assert_allclose(
            mesh_aabb(mesh), [[-1, -half_height, -1], [1, half_height, 1]], atol=1e-12
        )


def test_primitive_volumes_match_their_polyhedra() -> None:
    (cube,) = primitive_meshes("cubeSolid")
    np.testing.assert_allclose(_volume(cube), 8.0, rtol=1e-12)
    # Icosphere (80 faces): inscribed in the unit sphere and enclosing the sphere of its
    # smallest face distance r_in, so 4/3 pi r_in^3 <= V <= 4/3 pi.
    (ico,) = primitive_meshes("icosphereSolid_subdivs_1")
    assert len(ico.faces) == 80 and len(ico.vertices) == 42
    triangles = ico.vertices[ico.faces]
    normals = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    r_in = np.min(np.einsum("ij,ij->i", normals, triangles[:, 0]))
    assert 4.0 / 3.0 * np.pi * r_in**3 <= _volume(ico) <= 4.0 / 3.0 * np.pi
    assert _volume(ico) > 0.85 * 4.0 / 3.0 * np.pi  # subdivision 1 is already close
    np.testing.assert_allclose(np.linalg.norm(ico.vertices, axis=1), 1.0, rtol=1e-12)
    # 12-gon prism: area of the regular 12-gon (12/2 sin 30 deg = 3) times height 2.
    (cylinder,) = primitive_meshes(
        "cylinderSolid_rings_1_segments_12_halfLen_1_useTexCoords_false_useTangents_false"
        "_capEnds_true"
    )
    np.testing.assert_allclose(_volume(cylinder), 6.0, rtol=1e-12)
    # 12-gon pyramid: base area 3, height 2.5 -> V = 3 * 2.5 / 3.
    (cone,) = primitive_meshes(
        "coneSolid_segments_12_halfLen_1.25_rings_1_useTexCoords_false_useTangents_false"
        "_capEnd_true"
    )
    np.testing.assert_allclose(_volume(cone), 2.5, rtol=1e-12)


def test_primitive_handle_parser_reads_parameters_and_rejects_bad_handles() -> None:
    kind, params = parse_primitive_handle(
        "capsule3DSolid_hemiRings_5_cylRings_2_segments_16_halfLen_1.75"
        "_useTexCoords_true_useTangents_true"
    )
    assert kind == "capsule"
    assert params["hemiRings"] == 5 and params["cylRings"] == 2 and params["segments"] == 16
    assert params["halfLen"] == 1.75 and params["useTexCoords"] is True
    assert params["wireframe"] is False
    (capsule,) = primitive_meshes(
        "capsule3DSolid_hemiRings_5_cylRings_2_segments_16_halfLen_1.75"
        "_useTexCoords_true_useTangents_true"
    )
    np.testing.assert_allclose(mesh_aabb(capsule)[:, 1], [-2.75, 2.75], atol=1e-12)
    (uncapped,) = primitive_meshes(
        "cylinderSolid_rings_3_segments_8_halfLen_0.5_useTexCoords_false_useTangents_false"
        "_capEnds_false"
    )
    assert len(uncapped.faces) == 3 * 8 * 2  # side quads only
    bad = [
        "sphereSolid",
        "cubeSolid_extra_1",
        "icosphereSolid_subdivs_x",
        "icosphereSolid_subdivs_-1",
        "coneWireframe_segments_2_halfLen_1",
        "cylinderWireframe_rings_1_segments_32_halfLen_0",
        "cylinderWireframe_segments_32_rings_1_halfLen_1",
        "uvSphereSolid_rings_8_segments_16_useTexCoords_maybe_useTangents_false",
    ]
    for handle in bad:
        with pytest.raises(ValueError, match="handle"):
            primitive_meshes(handle)
