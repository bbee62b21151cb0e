"""Camera intrinsics, projection and input validation (docs/physics.md, validation)."""

from __future__ import annotations

import dataclasses
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


@pytest.mark.parametrize("value", [np.nan, np.inf, -np.inf])
@pytest.mark.parametrize("entry", [(0, 0), (1, 2), (2, 3), (3, 3)])
def test_pose_with_a_single_non_finite_entry_is_rejected(value, entry):
    pose = np.eye(4)
    pose[entry] = value
    with pytest.raises(ValueError, match="finite|last row"):
        check_pose(pose)
    with pytest.raises(ValueError, match="world_from_camera"):
        invert_rigid(pose)


@pytest.mark.parametrize("last_row", [(0, 0, 0, 2), (0, 0, 1e-6, 1), (1, 0, 0, 1)])
def test_pose_that_is_not_affine_is_rejected(last_row):
    pose = np.eye(4)
    pose[3] = last_row
    with pytest.raises(ValueError, match="last row"):
        check_pose(pose, "camera_pose")
    # a last row within 1e-9 of [0, 0, 0, 1] is accepted and returned as float64
    pose[3] = (0, 0, 1e-12, 1)
    assert check_pose(pose).dtype == np.float64


def test_invert_of_a_scaled_pose_is_its_matrix_inverse():
    # a scaled camera node: R is not orthonormal, so R^T is not its inverse
    angle = 0.4
    pose = np.eye(4)
    pose[:3, :3] = 2.0 * np.array(
        [[math.cos(angle), -math.sin(angle), 0], [math.sin(angle), math.cos(angle), 0], [0, 0, 1]]
    )
    pose[:3, 3] = [0.5, -1.0, 2.0]
    np.testing.assert_allclose(invert_rigid(pose) @ pose, np.eye(4), atol=1e-12)
    np.testing.assert_allclose(pose @ invert_rigid(pose), np.eye(4), atol=1e-12)


def test_rigid_inverse_maps_the_camera_position_to_the_origin():
    # camera at (1, 2, 3) looking down world -X (rotated +90 degrees about Y)
    pose = np.eye(4)
    pose[:3, :3] = [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]
    pose[:3, 3] = [1.0, 2.0, 3.0]
    camera_from_world = invert_rigid(pose)
    np.testing.assert_allclose(camera_from_world @ [1, 2, 3, 1], [0, 0, 0, 1], atol=1e-15)
    # a world point 5 m along world -X from the camera is 5 m down the camera's -Z axis
    np.testing.assert_allclose(camera_from_world @ [-4, 2, 3, 1], [0, 0, -5, 1], atol=1e-15)


def test_orthographic_pixel_rays_are_parallel_to_the_view_axis():
    rays = Camera((3, 5), subtype="orthographic", ortho_scale=0.5).pixel_rays()
    assert rays.shape == (3, 5, 3)
    np.testing.assert_array_equal(rays, np.broadcast_to([0.0, 0.0, -1.0], (3, 5, 3)))


def test_points_at_depth_d_on_pinhole_rays_have_depth_d_at_the_pixel_center():
    camera = Camera((6, 8), hfov=75.0)
    rays = camera.pixel_rays()
    np.testing.assert_array_equal(rays[..., 2], -1.0)  # z-component -1: d * ray has depth d
    # the corner pixel (0, 0): center (0.5, 0.5) is up-left of the principal point
    assert rays[0, 0, 0] < 0.0 < rays[0, 0, 1]
    pixels, depth = camera.project(3.5 * rays.reshape(-1, 3))
    np.testing.assert_allclose(depth, 3.5)
    cols, rows = np.meshgrid(np.arange(8) + 0.5, np.arange(6) + 0.5)
    np.testing.assert_allclose(pixels, np.column_stack([cols.ravel(), rows.ravel()]), atol=1e-12)


@pytest.mark.parametrize("shape", [(5, 4), (5, 2), (3,), (2, 3, 3), (0, 4)])
def test_project_rejects_points_not_of_shape_n_by_3(shape):
    with pytest.raises(ValueError, match=r"points_camera must have shape \(N, 3\)"):
        Camera((10, 10)).project(np.ones(shape))


def test_camera_defaults_are_habitats_and_the_camera_is_frozen():
    camera = Camera((10, 20))
    assert (camera.hfov, camera.near, camera.far) == (90.0, 0.01, 1000.0)
    assert (camera.subtype, camera.ortho_scale) == ("pinhole", 0.1)
    assert camera.is_pinhole and (camera.height, camera.width) == (10, 20)
    with pytest.raises(dataclasses.FrozenInstanceError):
        camera.hfov = 60.0  # type: ignore[misc]
    # numbers of any real type are stored as float, numpy ints as int
    camera = Camera((np.int64(4), 6), hfov=np.float32(60.0), near=1, far=np.int32(9))
    assert type(camera.hfov) is float and type(camera.near) is float
    assert camera.resolution == (4, 6) and type(camera.resolution[0]) is int
    assert not Camera((4, 6), subtype="orthographic").is_pinhole


def test_orthographic_focal_length_is_pixels_per_meter():
    camera = Camera((40, 100), subtype="orthographic", ortho_scale=0.2)
    # Habitat's orthographic view is 1 / ortho_scale meters wide: W ortho_scale = 100 * 0.2
    assert camera.fx == camera.fy == pytest.approx(20.0)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"resolution": (1, 1)},
        {"resolution": (10, 10), "hfov": 179.9},
        {"resolution": (10, 10), "near": 0.5, "far": 0.5000001},
        {"resolution": (4096, 4096)},
    ],
)
def test_limit_camera_parameters_are_accepted(kwargs):
    Camera(**kwargs)


@pytest.mark.parametrize(
    "kwargs, error, fragment",
    [
        ({"resolution": (True, 10)}, ValueError, "resolution"),
        ({"resolution": (10, -3)}, ValueError, "resolution"),
        ({"resolution": None}, ValueError, "resolution"),
        ({"resolution": (4097, 4096)}, ValueError, "camera resolution"),
        ({"resolution": (10, 10), "near": 1.0, "far": 1.0}, ValueError, "far"),
        ({"resolution": (10, 10), "hfov": True}, TypeError, "hfov"),
        ({"resolution": (10, 10), "near": "0.1"}, TypeError, "near"),
        ({"resolution": (10, 10), "ortho_scale": -1.0}, ValueError, "ortho_scale"),
        ({"resolution": (10, 10), "ortho_scale": float("nan")}, ValueError, "ortho_scale"),
    ],
)
def test_more_bad_camera_parameters_are_rejected_by_name(kwargs, error, fragment):
    with pytest.raises(error, match=fragment):
        Camera(**kwargs)
