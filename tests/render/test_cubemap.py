"""Wide-angle cameras: the camera models' rays and the cube-map resampling, checked against
hand geometry (a ray's face texel, a point's pixel, a plane's depth) and the plain reference."""

from __future__ import annotations

import math

import numpy as np
import pytest

from render import camera_models, cubemap
from render.camera import Camera
from render.frame import RenderMesh, render_frame

FOCAL, XI, ALPHA = (40.0, 40.0), -0.18, 0.59  # Habitat's default double sphere, a 96 px image


def test_face_texels_of_axis_rays_are_the_face_centers():
    size = 8
    rays = np.array(
        [[1.0, 0, 0], [-1.0, 0, 0], [0, 1.0, 0], [0, -1.0, 0], [0, 0, 1.0], [0, 0, -1.0]]
    )
    face, row, col = cubemap.face_texels(rays, size)
    np.testing.assert_array_equal(face, [0, 1, 2, 3, 4, 5])  # Habitat's +X -X +Y -Y +Z -Z
    np.testing.assert_array_equal(row, [4, 4, 4, 4, 4, 4])  # floor(S/2) for px = S/2
    np.testing.assert_array_equal(col, [4, 4, 4, 4, 4, 4])


def test_a_ray_lands_on_the_pinhole_pixel_of_its_face():
    # -Z face, f = S/2 = 50: (0.5, -0.2, -1) -> px = 50 + 50 * 0.5 = 75, py = 50 + 50 * 0.2 = 60
    face, row, col = cubemap.face_texels(np.array([[0.5, -0.2, -1.0]]), 100)
    assert (face[0], row[0], col[0]) == (5, 60, 75)
    # the +X face is the camera turned 90 degrees right: its right is the camera's +Z, so a
    # ray (1, 0, -0.5) has x_face = -0.5 and lands left of center: px = 50 - 25
    face, row, col = cubemap.face_texels(np.array([[1.0, 0.0, -0.5]]), 100)
    assert (face[0], row[0], col[0]) == (0, 50, 25)


def test_face_poses_look_along_the_camera_axes():
    pose = np.eye(4)
    pose[:3, 3] = [1.0, 2.0, 3.0]
    faces = cubemap.face_poses(pose)
    looks = -faces[:, :3, 2]  # each face camera looks down its local -Z
    np.testing.assert_allclose(
        looks, [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]
    )
    np.testing.assert_allclose(faces[:, :3, 3], np.tile([1.0, 2.0, 3.0], (6, 1)))


def test_equirectangular_rays_center_forward_left_quarter_left_top_up():
    rays = camera_models.equirectangular_rays((64, 128))
    np.testing.assert_allclose(np.linalg.norm(rays, axis=-1), 1.0, atol=1e-12)
    # pixel centers sit half a pixel off the exact directions: tolerance of one pixel's angle
    step = math.pi / 64
    np.testing.assert_allclose(rays[32, 64], [0, 0, -1], atol=step)
    np.testing.assert_allclose(rays[32, 32], [-1, 0, 0], atol=step)
    np.testing.assert_allclose(rays[0, 64], [0, 1, 0], atol=step)


def test_projections_invert_the_rays_at_every_pixel_center():
    resolution = (48, 96)
    rays = camera_models.equirectangular_rays(resolution).reshape(-1, 3)
    pixels = camera_models.equirectangular_project(rays, resolution)
    cols, rows = np.meshgrid(np.arange(96) + 0.5, np.arange(48) + 0.5)
    np.testing.assert_allclose(pixels, np.stack([cols.ravel(), rows.ravel()], 1), atol=1e-9)

    fisheye = ((96, 96), FOCAL, (48.0, 48.0), XI, ALPHA)
    rays, valid = camera_models.double_sphere_rays(*fisheye)
    pixels = camera_models.double_sphere_project(rays[valid], *fisheye)
    cols, rows = np.meshgrid(np.arange(96) + 0.5, np.arange(96) + 0.5)
    expected = np.stack([cols[valid], rows[valid]], 1)
    np.testing.assert_allclose(pixels, expected, atol=1e-7)  # float64 round trip


def test_double_sphere_center_pixel_looks_forward_and_circle_edge_is_invalid():
    rays, valid = camera_models.double_sphere_rays((96, 96), FOCAL, (48.0, 48.0), XI, ALPHA)
    # the principal point sits on a pixel corner: the 4 central pixels are symmetric about -Z
    center = rays[47:49, 47:49].reshape(-1, 3).mean(0)
    np.testing.assert_allclose(center / np.linalg.norm(center), [0, 0, -1], atol=1e-12)
    # alpha > 0.5: pixels with r^2 > 1 / (2 alpha - 1) = 5.56 see nothing; with f = 20 px
    # the corner has r^2 = 2 (47.5 / 20)^2 = 11.3
    _, valid = camera_models.double_sphere_rays((96, 96), (20.0, 20.0), (48.0, 48.0), XI, ALPHA)
    assert valid[48, 48] and not valid[0, 0]
    radius_sq = ((np.arange(96) + 0.5 - 48.0) / 20.0) ** 2
    np.testing.assert_array_equal(
        valid, radius_sq[:, None] + radius_sq[None, :] <= 1.0 / (2 * ALPHA - 1)
    )


def _cube_faces(meshes: list[RenderMesh], size: int, world_from_camera=None):
    """Render the six faces (color, depth, ids stacked in Habitat's order)."""
    pose = np.eye(4) if world_from_camera is None else world_from_camera
    camera = Camera((size, size), hfov=90.0)
    frames = [render_frame(meshes, camera, face) for face in cubemap.face_poses(pose)]
    return (
        np.stack([f.rgba.copy() for f in frames]),
        np.stack([f.depth.copy() for f in frames]),
        np.stack([f.ids.copy() for f in frames]),
    )


def _wall(depth: float, half: float, semantic_id: int = 7) -> RenderMesh:
    vertices = np.array(
        [[-half, -half, -depth], [half, -half, -depth], [half, half, -depth], [-half, half, -depth]]
    )
    return RenderMesh(
        vertices,
        np.array([[0, 1, 2], [0, 2, 3]]),
        base_color=np.array([10, 200, 30, 255], np.uint8),
        lit=False,
        semantic_id=semantic_id,
    )


def test_a_wall_reads_its_z_depth_through_the_fisheye_and_the_panorama():
    # a wall at z = -2 filling the -Z face: every ray hitting that face reads depth 2
    _, depth, ids = _cube_faces([_wall(2.0, 10.0)], 32)
    rays, valid = camera_models.double_sphere_rays((64, 64), (25.0, 25.0), (32.0, 32.0), XI, ALPHA)
    fisheye_depth = cubemap.resample(depth, rays, valid)
    face, _, _ = cubemap.face_texels(np.where(valid[..., None], rays, (0, 0, -1.0)), 32)
    front = valid & (face == 5)
    assert front.sum() > 500
    np.testing.assert_array_equal(fisheye_depth[front], np.float32(2.0))
    assert np.all(cubemap.resample(ids, rays, valid)[front] == 7)
    assert np.all(fisheye_depth[~valid] == 0)

    pano = camera_models.equirectangular_rays((32, 64))
    pano_depth = cubemap.resample(depth, pano)
    assert pano_depth[16, 32] == np.float32(2.0)  # the center looks at the wall
    assert pano_depth[16, 0] == 0.0  # behind the camera: nothing


def test_a_small_marker_appears_at_its_projected_pixel():
    # a 6 cm square at camera (0.5, 0.3, -2): its fisheye pixel is double_sphere_project's
    marker = _wall(2.0, 0.03, semantic_id=3)
    marker = RenderMesh(
        marker.vertices + [0.5, 0.3, 0.0], marker.faces, base_color=marker.base_color, lit=False,
        semantic_id=3,
    )  # fmt: skip
    _, _, ids = _cube_faces([marker], 256)
    model = ((128, 128), (50.0, 50.0), (64.0, 64.0), XI, ALPHA)
    rays, valid = camera_models.double_sphere_rays(*model)
    image = cubemap.resample(ids, rays, valid)
    rows, cols = np.nonzero(image == 3)
    px, py = camera_models.double_sphere_project(np.array([[0.5, 0.3, -2.0]]), *model)[0]
    assert len(rows) >= 1
    assert abs(cols.mean() + 0.5 - px) <= 1.0 and abs(rows.mean() + 0.5 - py) <= 1.0


@pytest.mark.parametrize("channels", [(), (4,)])
def test_vectorized_resampling_equals_the_reference_bit_for_bit(channels):
    rng = np.random.default_rng(4)
    faces = rng.integers(0, 255, size=(6, 7, 7, *channels)).astype(np.uint8)
    rays = rng.normal(size=(9, 11, 3))
    rays[0, 0] = [1.0, 1.0, -1.0]  # a tie between three axes
    rays[0, 1] = [0.0, -2.0, 2.0]  # a tie between two
    valid = rng.random((9, 11)) > 0.2
    fast = cubemap.resample(faces, rays, valid, background=5)
    plain = cubemap.resample(faces, rays, valid, background=5, reference=True)
    np.testing.assert_array_equal(fast, plain)
    assert np.all(fast[~valid] == 5)


def test_cubemap_size_rule_and_bad_sizes():
    assert cubemap.cubemap_size((48, 96)) == 48  # min(H, W), Habitat's default
    assert cubemap.cubemap_size((48, 96), 20) == 20
    for bad in (0, -3, 2.5, True):
        with pytest.raises(ValueError, match="cubemap_size"):
            cubemap.cubemap_size((48, 96), bad)  # type: ignore[arg-type]


# -- bilinear color --------------------------------------------------------------------------
def gradient_faces(size=4):
    """Faces whose texel (row j, column i) holds ``10 i + 50 j`` in every channel."""
    j, i = np.mgrid[0:size, 0:size]
    values = (10 * i + 50 * j).astype(np.uint8)
    return np.repeat(np.repeat(values[None, :, :, None], 6, axis=0), 4, axis=3)


def test_bilinear_color_weights_the_four_texels_around_the_point():
    faces = gradient_faces()  # S = 4, the -Z face (index 5) has the identity rotation
    # ray (x, y, -1) -> px = 2 + 2x, py = 2 - 2y; texel centers at i + 1/2
    rays = np.array([[[0.0, 0.0, -1.0], [0.25, 0.0, -1.0], [-0.9, 0.0, -1.0], [0.0, 0.125, -1.0]]])
    out = cubemap.resample(faces, rays, bilinear=True)[0, :, 0]
    # px = 2: halfway between columns 1 and 2 (10, 20) and rows 1 and 2 (50, 100) -> 15 + 75
    assert out[0] == 90
    assert out[1] == 20 + 75  # px = 2.5: exactly column 2's center
    assert out[2] == 0 + 75  # px = 0.2: left of column 0's center, clamped to the face
    # py = 1.75: b = 0.25 between rows 1 and 2 (50, 100) -> 62.5; + 15 = 77.5, rounded up
    assert out[3] == 78
    nearest = cubemap.resample(faces, rays)[0, :, 0]
    assert nearest[0] == 20 + 100  # the nearest texel: floor(2) = column 2, row 2


@pytest.mark.parametrize("channels", [3, 4])
def test_bilinear_vectorized_equals_the_reference_bit_for_bit(channels):
    rng = np.random.default_rng(9)
    faces = rng.integers(0, 256, size=(6, 5, 5, channels)).astype(np.uint8)
    rays = rng.normal(size=(8, 10, 3))
    rays[0, 0] = [1.0, 1.0, -1.0]  # corners and ties
    valid = rng.random((8, 10)) > 0.2
    fast = cubemap.resample(faces, rays, valid, background=7, bilinear=True)
    plain = cubemap.resample(faces, rays, valid, background=7, reference=True, bilinear=True)
    np.testing.assert_array_equal(fast, plain)
    assert np.all(fast[~valid] == 7)


def test_bilinear_needs_8_bit_color_faces():
    with pytest.raises(ValueError, match="bilinear"):
        cubemap.resample(np.zeros((6, 4, 4), np.float32), np.ones((2, 2, 3)), bilinear=True)
