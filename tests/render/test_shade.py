"""The fast shading kernels give the bits of the plain ones (``RenderSettings`` fields
``fast_shading``, ``pixel_center_tables``, ``paired_attributes``): kernel by kernel, and for
whole frames of scenes that mix every material kind (flat, vertex colors, textures with
and without tint, two textures, lit and unlit, Gouraud), perspective and orthographic."""

from __future__ import annotations

import numpy as np
import pytest

from render import packed_rgba, shade
from render.camera import Camera
from render.frame import RenderMesh, RenderScene, render_frame
from render.resolve import AttributePlanes, VisiblePixels
from render.settings import DEFAULT_SETTINGS, RenderSettings

RNG_SEED = 15


def settings_for(fast: bool) -> RenderSettings:
    """The default (fast) kernels, or the plain ones everywhere."""
    return DEFAULT_SETTINGS if fast else RenderSettings.plain()


@pytest.mark.parametrize("uv_origin", ["bottom", "top"])
@pytest.mark.parametrize("size", [(1, 1), (3, 5), (64, 32)])
def test_fast_bilinear_sampler_matches_the_plain_one(uv_origin, size):
    rng = np.random.default_rng(RNG_SEED)
    texels = rng.integers(0, 2**32, size=size, dtype=np.uint64).astype(np.uint32)
    padded = packed_rgba.pad_texture_wrap(texels)
    # wrapped, negative and texel-center coordinates, and the exact edges 0 and 1
    u = np.concatenate(
        [rng.uniform(-4, 4, 5000), (np.arange(size[1]) + 0.5) / size[1], [0.0, 1.0, -1.0, 2.5]]
    ).astype(np.float32)
    v = np.concatenate(
        [rng.uniform(-4, 4, 5000), (np.arange(size[1]) + 0.5) / size[1], [1.0, 0.0, -0.0, 3.0]]
    ).astype(np.float32)
    u_before, v_before = u.copy(), v.copy()
    plain = packed_rgba.sample_bilinear(padded, u, v, uv_origin)
    fast = packed_rgba.sample_bilinear_fast(padded, u, v, uv_origin)
    np.testing.assert_array_equal(fast, plain)
    np.testing.assert_array_equal(u, u_before)  # inputs untouched
    np.testing.assert_array_equal(v, v_before)


def test_in_place_light_modulation_matches_the_plain_one():
    rng = np.random.default_rng(RNG_SEED)
    packed = rng.integers(0, 2**32, size=4000, dtype=np.uint64).astype(np.uint32)
    factor = np.concatenate([rng.uniform(0, 1, 3996), [0.0, 1.0, 0.5, 0.998]]).astype(np.float32)
    expected = packed_rgba.modulate_packed(packed, factor)
    packed_rgba.modulate_packed_inplace(packed, factor)
    np.testing.assert_array_equal(packed, expected)
    assert np.all(
        packed_rgba.modulate_packed(packed, np.ones(4000, np.float32)) == packed
    )  # W = 256


@pytest.mark.parametrize("subtype", ["pinhole", "orthographic"])
def test_paired_two_channel_attributes_match_the_per_channel_loop(subtype):
    camera = Camera((37, 53), subtype=subtype)
    rng = np.random.default_rng(RNG_SEED)
    n_triangles = 40
    planes = rng.normal(0.0, 2.0, (3, 3, n_triangles))
    uvs = rng.uniform(-3.0, 3.0, (3, 2, n_triangles))  # (corners, channels, triangles)
    pixel = np.sort(rng.choice(37 * 53, 500, replace=False)).astype(np.int64)
    visible = VisiblePixels(
        pixel,
        rng.integers(0, n_triangles, len(pixel)),
        rng.uniform(0.1, 30.0, len(pixel)).astype(np.float32),
        camera,
    )
    paired = AttributePlanes(planes, uvs, camera, paired=True).evaluate(visible)
    plain = AttributePlanes(planes, uvs, camera, paired=False).evaluate(visible)
    assert paired.shape == plain.shape == (2, len(pixel)) and paired.dtype == np.float32
    bits = np.ascontiguousarray(paired).view(np.uint32)
    np.testing.assert_array_equal(bits, plain.view(np.uint32))  # bit for bit


@pytest.mark.parametrize("subtype", ["pinhole", "orthographic"])
def test_pixel_center_tables_match_the_divmod_formula(subtype):
    camera = Camera((37, 53), subtype=subtype)
    rng = np.random.default_rng(RNG_SEED)
    scattered = np.sort(rng.choice(37 * 53, 300, replace=False))
    for pixel in (scattered, np.arange(100, 700), np.arange(37 * 53), np.arange(0)):
        fast, plain = (
            VisiblePixels(
                pixel.astype(np.int64),
                np.zeros(len(pixel), np.int64),
                np.ones(len(pixel), np.float32),
                camera,
                tables,
            ).centered_coordinates()
            for tables in (True, False)
        )
        for a, b in zip(fast, plain, strict=True):
            assert a.dtype == b.dtype == np.float32
            np.testing.assert_array_equal(a, b)


def _mixed_scene(rng: np.random.Generator) -> list[RenderMesh]:
    """A floor with a texture, a tinted textured wall, a vertex-colored lit sphere, flat
    lit boxes, a second texture with vertex colors and a Gouraud-shaded mesh."""
    import trimesh

    floor = np.array([[-4, -1, 1], [4, -1, 1], [4, -1, -9], [-4, -1, -9]], float)
    quad = np.array([[0, 1, 2], [0, 2, 3]])
    tiles = np.array([[0, 0], [6, 0], [6, 8], [0, 8]], float)  # repeats: wrap-around
    meshes = [
        RenderMesh(
            floor,
            quad,
            uvs=tiles,
            texture=rng.integers(0, 256, (32, 16, 3), np.uint8),
            lit=True,
            semantic_id=1,
        ),
        RenderMesh(
            floor[:, [0, 2, 1]] * [1, -1, 1] + [0, 0, -5],
            quad,
            uvs=tiles * 0.3,
            texture=rng.integers(0, 256, (8, 8, 4), np.uint8),
            uv_origin="top",
            base_color=np.array([200, 150, 90, 255], np.uint8),
            semantic_id=2,
        ),
    ]
    sphere = trimesh.creation.icosphere(subdivisions=2, radius=0.7)
    colors = rng.integers(0, 256, (len(sphere.vertices), 4), np.uint8)
    pose = np.eye(4)
    pose[:3, 3] = [-1.0, 0.0, -4.0]
    meshes.append(
        RenderMesh(
            sphere.vertices, sphere.faces, pose, vertex_colors=colors, lit=True, semantic_id=3
        )
    )
    smooth_pose = np.eye(4)
    smooth_pose[:3, 3] = [1.2, 0.2, -3.5]
    meshes.append(
        RenderMesh(
            sphere.vertices,
            sphere.faces,
            smooth_pose,
            lit=True,
            normals=sphere.vertex_normals,
            semantic_id=4,
            uvs=sphere.vertices[:, :2] + 0.5,
            vertex_colors=colors,
            texture=rng.integers(0, 256, (16, 16, 3), np.uint8),
        )
    )
    box = trimesh.creation.box(extents=(0.5, 0.4, 0.3))
    for i in range(3):
        box_pose = np.eye(4)
        box_pose[:3, :3] = trimesh.transformations.rotation_matrix(0.5 + i, (1, 1, 0))[:3, :3]
        box_pose[:3, 3] = [-0.8 + 0.9 * i, -0.6, -2.0 - 0.4 * i]
        meshes.append(
            RenderMesh(
                box.vertices,
                box.faces,
                box_pose,
                lit=i != 1,
                base_color=np.array([220, 40 * i, 90, 255], np.uint8),
                semantic_id=10 + i,
            )
        )
    return meshes


@pytest.mark.parametrize("subtype", ["pinhole", "orthographic"])
@pytest.mark.parametrize("cull", [False, True])
def test_fast_and_plain_shading_render_the_same_frame(subtype, cull):
    rng = np.random.default_rng(RNG_SEED)
    scene = RenderScene(_mixed_scene(rng))
    camera = Camera((90, 120), hfov=80.0, subtype=subtype)
    pose = np.eye(4)
    pose[:3, 3] = [0.0, 0.3, 0.5]
    frames = {}
    for fast in (False, True):
        frame = render_frame(scene, camera, pose, cull_back_faces=cull, settings=settings_for(fast))
        frames[fast] = {name: getattr(frame, name).copy() for name in ("rgba", "depth", "ids")}
    for name in ("rgba", "depth", "ids"):
        np.testing.assert_array_equal(frames[True][name], frames[False][name], err_msg=name)
    assert len(np.unique(frames[True]["ids"])) >= 6  # every kind of mesh is on screen


def test_a_screen_filled_by_one_texture_takes_the_single_texture_branch():
    """Every pixel textured by one mesh (the robot's view of a textured stage): the branch
    without selections gives the plain path's bits, lit and unlit."""
    rng = np.random.default_rng(RNG_SEED)
    camera = Camera((64, 96), hfov=90.0)
    wall = np.array([[-9, -9, -2], [9, -9, -2], [9, 9, -3], [-9, 9, -3]], float)
    for lit in (False, True):
        mesh = RenderMesh(
            wall,
            np.array([[0, 1, 2], [0, 2, 3]]),
            uvs=rng.uniform(-2, 3, (4, 2)),
            texture=rng.integers(0, 256, (24, 40, 3), np.uint8),
            lit=lit,
        )
        scene = RenderScene([mesh])
        frames = []
        for fast in (False, True):
            frame = render_frame(scene, camera, np.eye(4), settings=settings_for(fast))
            frames.append(frame.rgba.copy())
        assert np.all(frames[0][..., 3] == 255)  # the wall covers the screen
        np.testing.assert_array_equal(frames[1], frames[0])


def test_a_mostly_textured_screen_samples_every_pixel_and_keeps_the_others(monkeypatch):
    """One texture on most pixels with flat, vertex-colored and lit boxes in front (the
    3rd-person view of the robot on a textured floor): sampling every pixel and keeping the
    textured ones (``RenderSettings.sample_all_above``) gives the plain path's bits."""
    import trimesh

    rng = np.random.default_rng(RNG_SEED)
    camera = Camera((64, 96), hfov=90.0)
    wall = np.array([[-9, -9, -3], [9, -9, -3], [9, 9, -4], [-9, 9, -4]], float)
    meshes = [
        RenderMesh(
            wall,
            np.array([[0, 1, 2], [0, 2, 3]]),
            uvs=rng.uniform(-2, 3, (4, 2)),
            texture=rng.integers(0, 256, (24, 40, 3), np.uint8),
            lit=True,
        )
    ]
    box = trimesh.creation.box(extents=(0.4, 0.3, 0.3))
    for i, colored in enumerate((False, True)):
        pose = np.eye(4)
        pose[:3, 3] = [-0.6 + 1.2 * i, 0.0, -1.5]
        colors = rng.integers(0, 256, (len(box.vertices), 4), np.uint8) if colored else None
        meshes.append(RenderMesh(box.vertices, box.faces, pose, vertex_colors=colors, lit=i == 0))
    scene = RenderScene(meshes)
    calls = []
    monkeypatch.setattr(shade, "np", _CountingCopyto(calls))
    frames = []
    for fast in (False, True):
        frame = render_frame(scene, camera, np.eye(4), settings=settings_for(fast))
        frames.append(frame.rgba.copy())
    assert calls, "the sample-all branch ran"
    kinds = len(np.unique(frames[0].reshape(-1, 4), axis=0))
    assert kinds > 100  # texture, boxes and light on screen
    np.testing.assert_array_equal(frames[1], frames[0])


class _CountingCopyto:
    """``numpy`` as seen by ``render.shade``, counting ``np.copyto`` calls."""

    def __init__(self, calls: list) -> None:
        self._calls = calls

    def __getattr__(self, name: str):
        return getattr(np, name)

    def copyto(self, *args, **kwargs):
        self._calls.append(1)
        return np.copyto(*args, **kwargs)
