"""render_frame outputs: colors, textures, lighting, ids, scene caching, bad input."""

from __future__ import annotations

import time

import numpy as np
import pytest

from render.camera import Camera
from render.frame import BACKGROUND_RGBA, FrameBuffers, RenderMesh, RenderScene, render_frame
from render.settings import RenderSettings
from render.shade import face_light_factors

H, W = 48, 80
QUAD_FACES = np.array([[0, 1, 2], [0, 2, 3]])


def pixel_quad(camera: Camera, col0: int, row0: int, n_cols: int, n_rows: int, depth: float):
    """Corners (bottom-left, bottom-right, top-right, top-left) of a fronto-parallel quad
    whose edges lie exactly on pixel boundaries [col0, col0 + n_cols) x [row0, row0 + n_rows)."""
    scale = depth if camera.is_pinhole else 1.0  # orthographic: no division by depth
    x0, x1 = ((c - camera.cx) * scale / camera.fx for c in (col0, col0 + n_cols))
    y_top, y_bottom = (-(r - camera.cy) * scale / camera.fy for r in (row0, row0 + n_rows))
    return np.array(
        [[x0, y_bottom, -depth], [x1, y_bottom, -depth], [x1, y_top, -depth], [x0, y_top, -depth]]
    )


def test_flat_unlit_triangle_renders_its_exact_color_and_alpha_255():
    camera = Camera((H, W))
    color = np.array([12, 34, 56, 78], np.uint8)  # alpha is ignored: drawn pixels are opaque
    mesh = RenderMesh(pixel_quad(camera, 10, 5, 30, 20, 2.0), QUAD_FACES, base_color=color)
    frame = render_frame([mesh], camera, np.eye(4))
    drawn = frame.depth > 0
    assert drawn.sum() == 30 * 20
    assert np.all(frame.rgba[drawn] == [12, 34, 56, 255])
    assert np.all(frame.rgba[~drawn] == BACKGROUND_RGBA)
    assert frame.rgba.dtype == np.uint8 and frame.rgba.shape == (H, W, 4)


@pytest.mark.parametrize(
    "uv_origin, subtype", [("top", "pinhole"), ("bottom", "pinhole"), ("top", "orthographic")]
)
def test_texture_mapped_one_texel_per_pixel_is_reproduced_exactly(uv_origin, subtype):
    camera = Camera((H, W), subtype=subtype, ortho_scale=0.3)
    rng = np.random.default_rng(3)
    texture = rng.integers(0, 256, size=(16, 16, 3), dtype=np.uint8)
    v_bottom, v_top = (1.0, 0.0) if uv_origin == "top" else (0.0, 1.0)
    uvs = np.array([[0, v_bottom], [1, v_bottom], [1, v_top], [0, v_top]], dtype=float)
    mesh = RenderMesh(
        pixel_quad(camera, 30, 12, 16, 16, 3.0),
        QUAD_FACES,
        uvs=uvs,
        texture=texture,
        uv_origin=uv_origin,
    )
    frame = render_frame([mesh], camera, np.eye(4))
    # every pixel center is a texel center: bilinear weights are 0 -> the texel itself
    np.testing.assert_array_equal(frame.rgba[12:28, 30:46, :3], texture)
    assert np.all(frame.rgba[12:28, 30:46, 3] == 255)


def test_bilinear_filter_interpolates_between_texel_centers():
    camera = Camera((H, W))
    texture = np.array([[[0, 0, 0], [255, 255, 255]]], dtype=np.uint8)  # 1 x 2 texels
    uvs = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
    mesh = RenderMesh(pixel_quad(camera, 8, 4, 64, 8, 2.0), QUAD_FACES, uvs=uvs, texture=texture)
    red = render_frame([mesh], camera, np.eye(4)).rgba[8, 8:72, 0].astype(float)
    u = (np.arange(64) + 0.5) / 64
    between = (u > 0.25) & (u < 0.75)  # between the two texel centers (no wrap-around)
    expected = (2 * u - 0.5) * 255  # col = u w - 0.5, value = col * 255
    # 8-bit fixed-point weights: within 1 level of the exact blend
    np.testing.assert_allclose(red[between], expected[between], atol=1.0)


def test_texture_on_a_receding_floor_is_perspective_correct():
    camera = Camera((H, W), hfov=90.0)
    near_z, far_z = 1.0, 9.0
    vertices = np.array([[-4, -1, -near_z], [4, -1, -near_z], [4, -1, -far_z], [-4, -1, -far_z]])
    uvs = np.array([[0.5, 0.0], [0.5, 0.0], [0.5, 1.0], [0.5, 1.0]])  # v: 0 near -> 1 far
    ramp = np.repeat(np.arange(256, dtype=np.uint8)[:, None, None], 3, axis=2)  # row i = i
    mesh = RenderMesh(vertices, QUAD_FACES, uvs=uvs, texture=ramp, uv_origin="top")
    frame = render_frame([mesh], camera, np.eye(4))
    rows = np.arange(H) + 0.5
    ray_v = -(rows - camera.cy) / camera.fy
    with np.errstate(divide="ignore"):
        depth = np.where(ray_v < 0, 1.0 / -ray_v, np.inf)  # floor at y = -1
    v = (depth - near_z) / (far_z - near_z)
    texel = v * 256 - 0.5  # texel-row coordinate of the exact (perspective) v
    usable = (texel > 0.5) & (texel < 254.5)
    assert usable.sum() > 5
    got = frame.rgba[:, W // 2, 0].astype(float)
    np.testing.assert_allclose(got[usable], texel[usable], atol=1.0)
    # screen-linear (affine) interpolation would be far off in the middle rows
    assert np.max(np.abs(got[usable] - texel[usable])) < 1.0


def test_vertex_colors_interpolate_barycentrically():
    camera = Camera((H, W))
    corners = pixel_quad(camera, 10, 4, 60, 40, 2.0)[[0, 1, 3]]  # one triangle
    colors = np.array([[255, 0, 0, 255], [0, 255, 0, 255], [0, 0, 255, 255]], np.uint8)
    mesh = RenderMesh(corners, np.array([[0, 1, 2]]), vertex_colors=colors)
    frame = render_frame([mesh], camera, np.eye(4))
    screen, _ = camera.project(corners)
    drawn = np.argwhere(frame.depth > 0)
    p = drawn[:, ::-1] + 0.5  # (px, py) pixel centers
    # screen-space barycentrics are exact for a fronto-parallel triangle
    t = np.column_stack([screen[1] - screen[0], screen[2] - screen[0]])
    b12 = np.linalg.solve(t, (p - screen[0]).T).T
    bary = np.column_stack([1 - b12.sum(axis=1), b12])
    expected = bary @ colors[:, :3].astype(float)
    got = frame.rgba[drawn[:, 0], drawn[:, 1], :3].astype(float)
    np.testing.assert_allclose(got, expected, atol=0.51 + 1e-3)  # rounding to uint8


def test_default_light_factors_top_side_bottom():
    normals = np.array([[0, 1, 0], [1, 0, 0], [0, 0, -1], [0, -1, 0], [0, 0, 0]], float)
    # top: 0.4 + 0.5 * 4 * 0.447 > 1 -> 1; side: 0.4 + 0.5 * 0.894; bottom/degenerate: ambient
    side = 0.4 + 0.5 * 1.0 / np.sqrt(1.25)
    np.testing.assert_allclose(face_light_factors(normals), [1.0, side, side, 0.4, 0.4], rtol=1e-6)


def test_lit_cube_faces_are_shaded_by_the_default_lights_unlit_are_not():
    camera = Camera((H, W))
    pose = np.eye(4)
    # camera above and in front of a unit cube, looking down 45 degrees
    c, s = np.cos(np.radians(-45)), np.sin(np.radians(-45))
    pose[:3, :3] = [[1, 0, 0], [0, c, -s], [0, s, c]]
    pose[:3, 3] = [0.0, 3.0, 3.0]
    corners = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
    faces = np.array(
        [[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1]]
        + [[2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]]
    )
    base = np.array([200, 100, 50, 255], np.uint8)
    for lit in (False, True):
        frame = render_frame([RenderMesh(corners, faces, base_color=base, lit=lit)], camera, pose)
        colors = {tuple(c) for c in frame.rgba[frame.depth > 0].tolist()}
        if not lit:
            assert colors == {(200, 100, 50, 255)}
        else:
            # top face: factor 1 (exact); front face (+z): 0.847 x base = (169.4, 84.7, 42.4),
            # within one level (8-bit fixed-point light weight, see render.shade)
            assert (200, 100, 50, 255) in colors and len(colors) == 2
            (side,) = colors - {(200, 100, 50, 255)}
            side_factor = 0.4 + 0.5 / np.sqrt(1.25)
            np.testing.assert_allclose(side[:3], side_factor * base[:3], atol=1.0)


def test_ids_buffer_holds_semantic_ids_and_zero_background():
    camera = Camera((H, W))
    left = RenderMesh(pixel_quad(camera, 0, 0, 40, 48, 2.0), QUAD_FACES, semantic_id=7)
    right = RenderMesh(pixel_quad(camera, 40, 0, 20, 48, 3.0), QUAD_FACES, semantic_id=2**32 - 1)
    frame = render_frame([left, right], camera, np.eye(4))
    assert frame.ids.dtype == np.uint32
    assert np.all(frame.ids[:, :40] == 7)
    assert np.all(frame.ids[:, 40:60] == 2**32 - 1)
    assert np.all(frame.ids[:, 60:] == 0)


def test_render_scene_poses_visibility_and_buffer_reuse_match_fresh_renders():
    camera = Camera((H, W))
    mesh = RenderMesh(pixel_quad(camera, 10, 10, 20, 20, 2.0), QUAD_FACES, semantic_id=1)
    scene = RenderScene([mesh])
    first = render_frame(scene, camera, np.eye(4))
    depth_before = first.depth.copy()
    moved = np.eye(4)
    moved[:3, 3] = [0.0, 0.0, -1.0]  # push the quad 1 m away
    scene.set_world_from_mesh(0, moved)
    second = render_frame(scene, camera, np.eye(4), buffers=first)
    assert second is first  # buffers reused
    assert second.depth.max() == pytest.approx(3.0, rel=1e-6)
    fresh = render_frame(
        [RenderMesh(mesh.vertices, QUAD_FACES, moved, semantic_id=1)], camera, np.eye(4)
    )
    np.testing.assert_array_equal(second.rgba, fresh.rgba)
    np.testing.assert_array_equal(second.depth, fresh.depth)
    assert not np.array_equal(depth_before, second.depth)
    scene.set_visible(0, False)
    hidden = render_frame(scene, camera, np.eye(4), buffers=second)
    assert not hidden.depth.any() and not hidden.ids.any()
    other = render_frame(scene, Camera((10, 12)), np.eye(4), buffers=hidden)
    assert other.depth.shape == (10, 12)


def test_rendering_is_bit_identical_across_calls():
    camera = Camera((H, W), hfov=70.0)
    rng = np.random.default_rng(1)
    vertices = rng.uniform(-1, 1, size=(60, 3)) + [0, 0, -3]
    faces = rng.integers(0, 60, size=(80, 3))
    colors = rng.integers(0, 256, size=(60, 4), dtype=np.uint8)
    mesh = RenderMesh(vertices, faces, vertex_colors=colors, lit=True)
    a = render_frame([mesh], camera, np.eye(4))
    b = render_frame(RenderScene([mesh]), camera, np.eye(4))
    for name in ("rgba", "depth", "ids"):
        assert getattr(a, name).tobytes() == getattr(b, name).tobytes()


def test_empty_scene_renders_background():
    frame = render_frame([], Camera((H, W)), np.eye(4))
    assert isinstance(frame, FrameBuffers)
    assert np.all(frame.rgba == BACKGROUND_RGBA) and not frame.depth.any() and not frame.ids.any()


@pytest.mark.parametrize(
    "kwargs, error, fragment",
    [
        ({"vertices": np.full((3, 3), np.nan)}, ValueError, "vertices"),
        ({"vertices": np.zeros((3, 2))}, ValueError, "vertices"),
        ({"faces": np.array([[0, 1, 3]])}, ValueError, "faces"),
        ({"faces": np.array([[0.0, 1.0, 2.0]])}, ValueError, "faces"),
        ({"world_from_mesh": np.eye(3)}, ValueError, "world_from_mesh"),
        ({"vertex_colors": np.zeros((2, 4))}, ValueError, "vertex_colors"),
        ({"vertex_colors": np.full((3, 4), 300)}, ValueError, "vertex_colors"),
        ({"texture": np.zeros((4, 4, 3), np.uint8)}, ValueError, "uvs"),
        ({"uvs": np.zeros((3, 2)), "texture": np.zeros((4, 4, 3))}, ValueError, "texture"),
        ({"uvs": np.full((3, 2), np.inf)}, ValueError, "uvs"),
        ({"base_color": (1, 2)}, ValueError, "base_color"),
        ({"semantic_id": -1}, ValueError, "semantic_id"),
        ({"lit": "yes"}, TypeError, "lit"),
        ({"uv_origin": "left"}, ValueError, "uv_origin"),
    ],
)
def test_bad_render_mesh_raises_naming_the_field(kwargs, error, fragment):
    args = {"vertices": np.eye(3), "faces": np.array([[0, 1, 2]]), **kwargs}
    with pytest.raises(error, match=fragment):
        RenderMesh(**args)


def test_bad_render_frame_arguments_raise():
    mesh = RenderMesh(np.eye(3), np.array([[0, 1, 2]]))
    with pytest.raises(ValueError, match="world_from_camera"):
        render_frame([mesh], Camera((H, W)), np.full((4, 4), np.nan))
    with pytest.raises(TypeError, match="camera"):
        render_frame([mesh], (H, W), np.eye(4))
    with pytest.raises(TypeError, match="meshes"):
        render_frame([mesh, "box"], Camera((H, W)), np.eye(4))
    scene = RenderScene([mesh])
    with pytest.raises(KeyError):
        scene.set_world_from_mesh(3, np.eye(4))
    with pytest.raises(ValueError, match="world_from_mesh"):
        scene.set_world_from_mesh(0, np.zeros((4, 4)))
    np.testing.assert_array_equal(scene.world_from_mesh[0], np.eye(4))  # unchanged


def test_lit_mesh_with_vertex_normals_is_gouraud_shaded_close_to_exact_lighting():
    trimesh = pytest.importorskip("trimesh")
    sphere = trimesh.creation.icosphere(subdivisions=4, radius=1.0)
    base = np.array([250, 250, 250, 255], np.uint8)
    pose = np.eye(4)
    pose[:3, 3] = [0.0, 0.0, -4.0]
    camera = Camera((H, W), hfov=60.0)
    smooth = RenderMesh(
        sphere.vertices, sphere.faces, pose, base_color=base, lit=True, normals=sphere.vertices
    )
    frame = render_frame([smooth], camera, np.eye(4))
    drawn = np.argwhere(frame.depth > 0)
    # exact lighting: the normal of the true sphere where each pixel's ray hits it
    rays = camera.pixel_rays()[drawn[:, 0], drawn[:, 1]]
    hit = rays * frame.depth[drawn[:, 0], drawn[:, 1], None]  # z-depth d: point = d * ray
    normals = hit - pose[:3, 3]
    exact = face_light_factors(normals)[:, None] * base[:3]
    got = frame.rgba[drawn[:, 0], drawn[:, 1], :3].astype(float)
    inner = np.linalg.norm(normals[:, :2], axis=1) < 0.9  # away from the silhouette
    # Gouraud interpolation of a 2562-vertex sphere: within 1.5 % of full scale (measured
    # 0.9 %; flat shading of the same mesh is off by 2.6 %)
    np.testing.assert_allclose(got[inner], exact[inner], atol=0.015 * 255)
    # flat shading of the same mesh shows facets: far fewer distinct colors
    flat = render_frame(
        [RenderMesh(sphere.vertices, sphere.faces, pose, base_color=base, lit=True)],
        camera,
        np.eye(4),
    )
    n_smooth = len({tuple(c) for c in frame.rgba[frame.depth > 0].tolist()})
    n_flat = len({tuple(c) for c in flat.rgba[flat.depth > 0].tolist()})
    assert n_smooth > n_flat


def test_uniform_vertex_colors_are_premultiplied_by_the_base_color():
    camera = Camera((H, W))
    vc = np.tile([50, 100, 150, 255], (4, 1)).astype(np.uint8)  # same color at every corner
    base = np.array([255, 128, 255, 255], np.uint8)
    mesh = RenderMesh(
        pixel_quad(camera, 5, 5, 20, 10, 2.0), QUAD_FACES, vertex_colors=vc, base_color=base
    )
    frame = render_frame([mesh], camera, np.eye(4))
    expected = np.rint(vc[0, :3] * base[:3].astype(float) / 255.0)  # vertex color * base / 255
    assert np.all(frame.rgba[frame.depth > 0][:, :3] == expected)


def test_rebuilding_a_scene_reuses_packed_textures_of_the_same_array():
    texture = np.zeros((8, 8, 4), np.uint8)
    uvs = np.zeros((3, 2))
    mesh = RenderMesh(np.eye(3), np.array([[0, 1, 2]]), uvs=uvs, texture=texture)
    first, second = RenderScene([mesh]), RenderScene([mesh])
    assert first.materials.textures[0] is second.materials.textures[0]
    other = RenderMesh(np.eye(3), np.array([[0, 1, 2]]), uvs=uvs, texture=texture + 1)
    packed_other = RenderScene([other]).materials.textures[0]
    assert packed_other is not first.materials.textures[0]
    assert packed_other.shape == (10, 10)  # 8 x 8 texels plus the wrap border


def grid_mesh(n: int, z: float, semantic_id: int) -> RenderMesh:
    """An n x n grid of quads (2 n^2 triangles) on [-1, 1]^2 at z, colored by position."""
    xs, ys = np.meshgrid(np.linspace(-1, 1, n + 1), np.linspace(-1, 1, n + 1))
    vertices = np.column_stack([xs.ravel(), ys.ravel(), np.full(xs.size, z)])
    colors = np.column_stack(
        [
            (xs.ravel() + 1) * 127,
            (ys.ravel() + 1) * 127,
            np.full(xs.size, 60),
            np.full(xs.size, 255),
        ]
    ).astype(np.uint8)
    i, j = np.meshgrid(np.arange(n), np.arange(n))
    v00 = (j * (n + 1) + i).ravel()
    faces = np.concatenate(
        [
            np.column_stack([v00, v00 + 1, v00 + n + 2]),
            np.column_stack([v00, v00 + n + 2, v00 + n + 1]),
        ]
    )
    return RenderMesh(vertices, faces, vertex_colors=colors, semantic_id=semantic_id)


def test_many_triangle_scenes_shade_the_same_with_or_without_the_winner_refinement():
    camera = Camera((H, W), hfov=60.0)
    meshes = [grid_mesh(70, -3.0, 1), grid_mesh(70, -4.0, 2)]  # 2 x 9800 triangles
    refined = render_frame(meshes, camera, np.eye(4))
    unrefined = RenderSettings(refine_used_above=10**9)
    plain = render_frame(meshes, camera, np.eye(4), settings=unrefined)
    np.testing.assert_array_equal(refined.rgba, plain.rgba)
    np.testing.assert_array_equal(refined.ids, plain.ids)
    assert np.all(refined.ids[H // 2 - 5 : H // 2 + 5, W // 2 - 5 : W // 2 + 5] == 1)


@pytest.mark.parametrize("refine_above", [10**9, 4])
def test_rows_of_a_frame_match_the_whole_frame_over_stale_buffers(refine_above):
    """``rows=`` rasterizes, resolves and shades only those rows, over buffers that hold
    another frame (stale z-buffer keys outside the rows must not matter), with and without
    the winner refinement of the shading inputs."""
    settings = RenderSettings(refine_used_above=refine_above, shade_band_pixels=4 * W)
    camera = Camera((H, W), hfov=60.0)  # bands of 4 rows
    scene = RenderScene([grid_mesh(12, -3.0, 1), grid_mesh(9, -4.0, 2)])
    pose = np.eye(4)
    pose[:3, 3] = [0.3, -0.2, 0.0]
    whole = render_frame(scene, camera, pose, settings=settings)
    expected = {name: getattr(whole, name).copy() for name in ("rgba", "depth", "ids")}
    buffers = render_frame(scene, camera, np.eye(4), settings=settings)  # another frame
    for first, end in ((0, 8), (8, H), (12, 20)):
        part = render_frame(scene, camera, pose, buffers, rows=(first, end), settings=settings)
        for name, value in expected.items():
            np.testing.assert_array_equal(getattr(part, name)[first:end], value[first:end])
        assert 0 < part.n_fragments < whole.n_fragments


def test_ids_false_skips_the_semantic_ids_and_changes_nothing_else():
    camera = Camera((H, W), hfov=60.0)
    scene = RenderScene([grid_mesh(6, -3.0, 7), grid_mesh(5, -4.0, 9)])
    pose = np.eye(4)
    pose[:3, 3] = [0.5, 0.4, 0.0]  # part of the view is background
    with_ids = render_frame(scene, camera, pose)
    buffers = render_frame(scene, camera, pose)
    buffers.ids[...] = 12345  # anything: it must stay as it is
    without = render_frame(scene, camera, pose, buffers, ids=False)
    np.testing.assert_array_equal(without.rgba, with_ids.rgba)
    np.testing.assert_array_equal(without.depth, with_ids.depth)
    assert np.all(without.ids == 12345)
    assert set(np.unique(with_ids.ids).tolist()) == {0, 7}  # the grid in front, background


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"triangle_batch": 0}, "triangle_batch must be an int >= 1, got 0"),
        ({"fragment_chunk": 2.5}, "fragment_chunk must be an int >= 1, got 2.5"),
        ({"fast_shading": 1}, "fast_shading must be a bool, got 1"),
        ({"light_all_above": 1.5}, "light_all_above must be a fraction in \\[0, 1\\], got 1.5"),
    ],
)
def test_bad_render_settings_are_refused_naming_the_value(changes, message):
    with pytest.raises(ValueError, match=message):
        RenderSettings(**changes)
    with pytest.raises(TypeError, match="settings must be a render.RenderSettings"):
        render_frame([], Camera((4, 4)), np.eye(4), settings={"fast_shading": False})


def test_render_settings_are_one_frozen_value():
    settings = RenderSettings.plain(shade_band_pixels=64)
    assert (settings.fast_shading, settings.pixel_center_tables) == (False, False)
    assert settings.replace(fast_shading=True).fast_shading and not settings.fast_shading
    assert hash(settings) == hash(RenderSettings.plain(shade_band_pixels=64))
    with pytest.raises(AttributeError):
        settings.fast_shading = True  # type: ignore[misc]


def test_stage_timings_are_wall_milliseconds_and_fragments_cover_the_pixels():
    camera = Camera((H, W))
    mesh = RenderMesh(pixel_quad(camera, 10, 5, 30, 20, 2.0), QUAD_FACES, base_color=(9, 9, 9))
    assert FrameBuffers.allocate(camera).n_fragments == 0  # nothing rendered yet
    start = time.perf_counter()
    frame = render_frame([mesh], camera, np.eye(4))
    wall_ms = (time.perf_counter() - start) * 1e3
    # the stages run back to back inside the call: their sum is most of its wall time
    total_ms = sum(frame.timings.values())
    assert 0.01 * wall_ms <= total_ms <= wall_ms
    assert frame.n_fragments >= 30 * 20  # at least one fragment per covered pixel


@pytest.mark.parametrize("shape", [(24, 40), (96, 160), (48, 40)])
def test_buffers_of_another_resolution_are_replaced_by_the_cameras(shape):
    camera = Camera((H, W))
    mesh = RenderMesh(pixel_quad(camera, 10, 5, 30, 20, 2.0), QUAD_FACES, base_color=(1, 2, 3))
    stale = render_frame([mesh], Camera(shape), np.eye(4))
    frame = render_frame([mesh], camera, np.eye(4), stale)
    assert frame.rgba.shape == (H, W, 4) and frame.depth.shape == (H, W)
    assert (frame.depth > 0).sum() == 30 * 20


@pytest.mark.parametrize("rows", [(1, H), (0, 3), (8, 4), (-4, 8), (0, H + 4)])
def test_rows_off_the_band_grid_or_the_image_are_rejected(rows):
    settings = RenderSettings(shade_band_pixels=4 * W)  # bands of 4 rows
    camera = Camera((H, W))
    mesh = RenderMesh(pixel_quad(camera, 10, 5, 30, 20, 2.0), QUAD_FACES, base_color=(1, 2, 3))
    with pytest.raises(ValueError, match="rows"):
        render_frame([mesh], camera, np.eye(4), rows=rows, settings=settings)
    # whole bands to the last row
    render_frame([mesh], camera, np.eye(4), rows=(4, H), settings=settings)
    # the last band of an image whose height is not a multiple of the band is valid too
    short = Camera((H - 2, W))
    part = render_frame([mesh], short, np.eye(4), rows=(H - 4, H - 2), settings=settings)
    assert part.depth.shape == (H - 2, W)


def test_an_image_wider_than_a_band_is_shaded_one_row_per_band():
    # shade_band_pixels // W = 16384 // 9000 = 1 row per band: any row range is whole bands
    camera = Camera((4, 9000), hfov=120.0)
    mesh = RenderMesh(pixel_quad(camera, 100, 0, 50, 4, 2.0), QUAD_FACES, base_color=(1, 2, 3))
    part = render_frame([mesh], camera, np.eye(4), rows=(1, 3))
    assert (part.depth[1:3] > 0).sum() == 2 * 50
    # one row per band: every row is on the band grid, but row -1 is still not in the image
    with pytest.raises(ValueError, match="rows"):
        render_frame([mesh], camera, np.eye(4), rows=(-1, 3))
