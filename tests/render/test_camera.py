"""Camera intrinsics, projection and input validation (VALIDATION.md section 5)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from render.camera import Camera, check_pose, invert_rigid


def test_focal_length_is_360_px_for_720_by_544_at_90_degrees():
    camera = Camera((544, 720), hfov=90.0)
    assert camera.fx == pytest.approx(360.0, rel=1e-12)
    assert camera.fy == camera.fx
    assert (camera.cx, camera.cy) == (360.0, 272.0)
    np.testing.assert_allclose(camera.intrinsics(), [[360, 0, 360], [0, 360, 272], [0, 0, 1]])


def test_project_matches_intrinsics_formula():
    camera = Camera((100, 160), hfov=70.0)
    fx = 80.0 / math.tan(math.radians(35.0))
    points = np.array([[0.3, -0.2, -2.0], [-1.0, 0.5, -4.5], [0.0, 0.0, -1.0]])
    pixels, depth = camera.project(points)
    z = -points[:, 2]
    expected = np.column_stack([80.0 + fx * points[:, 0] / z, 50.0 - fx * points[:, 1] / z])
    np.testing.assert_allclose(pixels, expected, rtol=1e-12)
    np.testing.assert_allclose(depth, z)


def test_orthographic_view_is_one_over_ortho_scale_meters_wide():
    # Habitat: orthographicProjection(nearPlaneSize / ortho_scale) with nearPlaneSize
    # (1, H / W): 1 / 0.25 = 4 m wide over 80 px (20 px per meter), 2.5 m tall over 50 px
    camera = Camera((50, 80), subtype="orthographic", ortho_scale=0.25)
    pixels, depth = camera.project(np.array([[0.0, 1.25, -3.0], [2.0, 0.0, -1.0]]))
    # y = +1.25 m is the top edge, x = +2 m the right edge
    np.testing.assert_allclose(pixels, [[40.0, 0.0], [80.0, 25.0]], atol=1e-12)
    np.testing.assert_allclose(depth, [3.0, 1.0])


def test_pixel_rays_pass_through_pixel_centers():
    camera = Camera((4, 6), hfov=60.0)
    rays = camera.pixel_rays()
    pixels, _ = camera.project(rays.reshape(-1, 3))
    cols, rows = np.meshgrid(np.arange(6) + 0.5, np.arange(4) + 0.5)
    np.testing.assert_allclose(pixels, np.column_stack([cols.ravel(), rows.ravel()]), atol=1e-12)


@pytest.mark.parametrize(
    "kwargs, fragment",
    [
        ({"resolution": (0, 10)}, "resolution"),
        ({"resolution": (10,)}, "resolution"),
        ({"resolution": (10.5, 10)}, "resolution"),
        ({"resolution": (10, 10), "hfov": 0.0}, "hfov"),
        ({"resolution": (10, 10), "hfov": 180.0}, "hfov"),
        ({"resolution": (10, 10), "hfov": float("nan")}, "hfov"),
        ({"resolution": (10, 10), "near": -1.0}, "near"),
        ({"resolution": (10, 10), "near": 2.0, "far": 1.0}, "far"),
        ({"resolution": (10, 10), "far": float("inf")}, "far"),
        ({"resolution": (10, 10), "subtype": "fisheye"}, "subtype"),
        ({"resolution": (10, 10), "ortho_scale": 0.0}, "ortho_scale"),
    ],
)
def test_bad_camera_parameters_raise_value_error_naming_them(kwargs, fragment):
    with pytest.raises(ValueError, match=fragment):
        Camera(**kwargs)


def test_non_numeric_hfov_raises_type_error():
    with pytest.raises(TypeError, match="hfov"):
        Camera((10, 10), hfov="wide")


@pytest.mark.parametrize(
    "pose", [None, np.eye(3), np.full((4, 4), np.nan), np.array([[1, 0, 0, 0]] * 4)]
)
def test_bad_pose_raises_value_error(pose):
    with pytest.raises(ValueError, match="world_from_camera"):
        check_pose(pose)


def test_invert_rigid_is_the_matrix_inverse():
    angle = 0.7
    pose = np.eye(4)
    pose[:3, :3] = [
        [math.cos(angle), 0, math.sin(angle)],
        [0, 1, 0],
        [-math.sin(angle), 0, math.cos(angle)],
    ]
    pose[:3, 3] = [1.0, 2.0, -3.0]
    np.testing.assert_allclose(invert_rigid(pose) @ pose, np.eye(4), atol=1e-12)
