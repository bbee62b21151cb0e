"""Rasterizer geometry: depth, coverage, fill rule, clipping (docs/physics.md, validation)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from matplotlib.path import Path
from scipy.spatial import ConvexHull

from render import raster
from render.camera import Camera
from render.frame import RenderMesh, render_frame

H, W = 60, 80


def quad(x0, x1, y0, y1, z, **kwargs) -> RenderMesh:
    """An axis-aligned rectangle in the plane z_world = z, facing +Z (counter-clockwise)."""
    vertices = np.array([[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]], dtype=float)
    return RenderMesh(vertices, np.array([[0, 1, 2], [0, 2, 3]]), **kwargs)


def pixel_centers(height: int, width: int) -> tuple[np.ndarray, np.ndarray]:
    """(H, W) arrays of pixel-center coordinates px, py."""
    return np.meshgrid(np.arange(width) + 0.5, np.arange(height) + 0.5)


def test_fronto_parallel_plane_reads_its_distance_at_covered_pixels_and_zero_elsewhere():
    camera = Camera((H, W), hfov=90.0)
    d = 3.7
    frame = render_frame([quad(-1.3, 2.1, -0.9, 1.6, -d)], camera, np.eye(4))
    # covered pixels: centers with x_left <= px < x_right and y_top <= py < y_bottom
    f = camera.fx
    px, py = pixel_centers(H, W)
    left, right = camera.cx + f * -1.3 / d, camera.cx + f * 2.1 / d
    top, bottom = camera.cy - f * 1.6 / d, camera.cy - f * -0.9 / d
    inside = (px >= left) & (px < right) & (py >= top) & (py < bottom)
    assert inside.sum() > 100
    # float32 depth: relative error of a few ulp (1 / (1 / d) rounded twice)
    np.testing.assert_allclose(frame.depth[inside], d, rtol=1e-6)
    assert np.all(frame.depth[~inside] == 0.0)
    assert frame.depth.dtype == np.float32


def test_depth_is_z_depth_not_ray_length_on_a_tilted_view():
    camera = Camera((H, W), hfov=100.0)
    frame = render_frame([quad(-50, 50, -50, 50, -2.0)], camera, np.eye(4))
    # a plane filling the view at z = -2: every pixel reads 2 (not 2 / cos(angle))
    np.testing.assert_allclose(frame.depth, 2.0, rtol=1e-6)


def test_small_square_lands_at_its_projected_pixel_position():
    camera = Camera((H, W), hfov=75.0)
    center = np.array([0.41, -0.23, -2.5])
    half = 0.05
    mesh = quad(center[0] - half, center[0] + half, center[1] - half, center[1] + half, center[2])
    frame = render_frame([mesh], camera, np.eye(4))
    rows, cols = np.nonzero(frame.depth > 0)
    z = -center[2]
    expected = (camera.cx + camera.fx * center[0] / z, camera.cy - camera.fy * center[1] / z)
    # the covered block is symmetric around the projected center up to half a pixel
    assert abs(cols.mean() + 0.5 - expected[0]) <= 0.5
    assert abs(rows.mean() + 0.5 - expected[1]) <= 0.5


def cube_mesh(pose: np.ndarray) -> RenderMesh:
    """The cube [-0.5, 0.5]^3 with outward counter-clockwise faces."""
    corners = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
    faces = np.array(
        [[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1]]
        + [[2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]]
    )
    return RenderMesh(corners, faces, world_from_mesh=pose)


def rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues rotation matrix (3, 3)."""
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


@pytest.mark.parametrize("cull", [False, True])
def test_unit_cube_covers_exactly_the_pixels_inside_its_projected_hull(cull):
    camera = Camera((120, 160), hfov=60.0)
    pose = np.eye(4)
    pose[:3, :3] = rotation([1.0, 2.0, 0.5], 0.9)
    pose[:3, 3] = [0.2, -0.1, -3.0]
    frame = render_frame([cube_mesh(pose)], camera, np.eye(4), cull_back_faces=cull)
    corners = cube_mesh(pose).vertices @ pose[:3, :3].T + pose[:3, 3]
    projected, _ = camera.project(corners)
    hull = ConvexHull(projected)
    polygon = Path(projected[hull.vertices])
    px, py = pixel_centers(120, 160)
    centers = np.column_stack([px.ravel(), py.ravel()])
    inside = polygon.contains_points(centers).reshape(120, 160)
    drawn = frame.depth > 0
    # pixel count vs exact polygon area: differs by less than the number of edge pixels
    perimeter = np.sum(
        np.linalg.norm(
            np.diff(projected[hull.vertices], axis=0, append=projected[hull.vertices[:1]]), axis=1
        )
    )
    assert abs(drawn.sum() - hull.volume) <= perimeter
    # and pixel by pixel: only centers within 1e-6 px of the outline may disagree
    near_edge = np.zeros_like(inside)
    for a, b in zip(hull.vertices, np.roll(hull.vertices, -1), strict=True):
        pa, pb = projected[a], projected[b]
        edge = pb - pa
        t = np.clip(((centers - pa) @ edge) / (edge @ edge), 0, 1)
        dist = np.linalg.norm(centers - (pa + t[:, None] * edge), axis=1)
        near_edge |= (dist < 1e-6).reshape(120, 160)
    assert np.array_equal(drawn & ~near_edge, inside & ~near_edge)


def coverage_count(screen: np.ndarray, height: int, width: int) -> np.ndarray:
    """How many triangles cover each pixel under the fill rule, (height, width) int.

    ``screen`` is (T, 3, 2): per triangle, 3 corners (px, py).
    """
    spans = raster.scanline_spans(screen.transpose(1, 2, 0), height, width)
    count = np.zeros(height * width, dtype=np.int64)
    for row, first, n in zip(spans.row, spans.col_first, spans.n_pixels, strict=True):
        count[row * width + first : row * width + first + n] += 1
    return count.reshape(height, width)


def test_two_triangles_sharing_an_edge_cover_each_pixel_once():
    # shared diagonal passing exactly through pixel centers (x = y + 0.5 lines),
    # outer edges exactly on pixel centers too
    a, b, c, d = (2.5, 2.5), (30.5, 2.5), (30.5, 30.5), (2.5, 30.5)
    screen = np.array([[a, b, c], [a, c, d]], dtype=float)
    count = coverage_count(screen, 40, 40)
    assert count.max() == 1
    # top-left rule: centers on the top (y = 2.5) and left (x = 2.5) edges are in,
    # those on the bottom (y = 30.5) and right (x = 30.5) edges are out: a 28 x 28 block
    assert count.sum() == 28 * 28
    assert np.all(count[2:30, 2:30] == 1)


def test_jittered_triangle_grid_covers_every_interior_pixel_exactly_once():
    rng = np.random.default_rng(7)
    n = 9  # (n + 1)^2 grid vertices with jittered interior, some on pixel centers
    xs, ys = np.meshgrid(np.linspace(3.0, 93.0, n + 1), np.linspace(2.0, 62.0, n + 1))
    grid = np.stack([xs, ys], axis=-1)
    grid[1:-1, 1:-1] += rng.uniform(-3.0, 3.0, size=(n - 1, n - 1, 2))
    grid[3, 4] = (np.floor(grid[3, 4, 0]) + 0.5, np.floor(grid[3, 4, 1]) + 0.5)  # on a center
    triangles = []
    for i in range(n):
        for j in range(n):
            p00, p01, p10, p11 = grid[i, j], grid[i, j + 1], grid[i + 1, j], grid[i + 1, j + 1]
            triangles += [[p00, p01, p11], [p00, p11, p10]]
    count = coverage_count(np.array(triangles), 70, 100)
    assert count.max() == 1  # no pixel drawn twice
    # every pixel center strictly inside the outer rectangle is drawn once (no cracks)
    px, py = pixel_centers(70, 100)
    interior = (px > 3.0) & (px < 93.0) & (py > 2.0) & (py < 62.0)
    assert np.all(count[interior] == 1)


def test_fan_around_a_vertex_on_a_pixel_center_covers_it_once():
    center = (20.5, 20.5)
    angles = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    ring = np.column_stack([20.5 + 15 * np.cos(angles), 20.5 + 15 * np.sin(angles)])
    screen = np.array([[center, ring[i], ring[(i + 1) % 8]] for i in range(8)])
    count = coverage_count(screen, 41, 41)
    assert count.max() == 1
    assert count[20, 20] == 1


def floor_mesh(height: float, extent: float) -> RenderMesh:
    """A horizontal square at y = height, |x|, |z| <= extent, facing up."""
    v = np.array(
        [[-extent, height, extent], [extent, height, extent], [extent, height, -extent]]
        + [[-extent, height, -extent]]
    )
    return RenderMesh(v, np.array([[0, 1, 2], [0, 2, 3]]))


def test_near_clipped_floor_has_exact_depth_below_the_horizon():
    camera = Camera((H, W), hfov=90.0, near=0.05)
    eye_height = 1.2
    frame = render_frame([floor_mesh(-eye_height, 100.0)], camera, np.eye(4))
    _, py = pixel_centers(H, W)
    v = -(py - camera.cy) / camera.fy  # ray (u, v, -1): the floor is hit at z = h / -v
    with np.errstate(divide="ignore"):
        expected = np.where(v < 0, eye_height / -v, 0.0)
    usable = (expected > 0) & (expected < 50.0)  # well inside the floor's extent
    np.testing.assert_allclose(frame.depth[usable], expected[usable], rtol=2e-6)
    assert np.all(frame.depth[v > 0] == 0.0)


@pytest.mark.parametrize("n_behind", [1, 2])
def test_triangle_crossing_the_near_plane_is_clipped_not_dropped(n_behind):
    camera = Camera((H, W), hfov=90.0, near=0.5)
    # a triangle in the plane x = 0.3 (seen edge-on would be empty): use a tilted plane
    z_front, z_back = -3.0, 1.0  # z_back is behind the camera
    zs = [z_back] * n_behind + [z_front] * (3 - n_behind)
    vertices = np.array([[-1.0, -0.4, zs[0]], [1.0, -0.4, zs[1]], [0.0, -0.4, zs[2]]])
    frame = render_frame([RenderMesh(vertices, np.array([[0, 1, 2]]))], camera, np.eye(4))
    drawn = frame.depth > 0
    assert drawn.any()
    # everything drawn lies on the plane y = -0.4 in front of the near plane
    _, py = pixel_centers(H, W)
    v = -(py - camera.cy) / camera.fy
    np.testing.assert_allclose(frame.depth[drawn], (0.4 / -v)[drawn], rtol=2e-6)
    assert frame.depth[drawn].min() >= camera.near * (1 - 1e-6)


def test_triangle_entirely_behind_the_camera_draws_nothing():
    camera = Camera((H, W))
    vertices = np.array([[-1.0, -1.0, 2.0], [1.0, -1.0, 2.0], [0.0, 1.0, 2.0]])
    frame = render_frame([RenderMesh(vertices, np.array([[0, 1, 2]]))], camera, np.eye(4))
    assert not np.any(frame.depth)


def test_far_plane_discards_fragments_beyond_it():
    camera = Camera((H, W), hfov=90.0, far=5.0)
    frame = render_frame([floor_mesh(-1.0, 100.0)], camera, np.eye(4))
    assert frame.depth.max() <= 5.0
    assert frame.depth.max() > 4.5


def test_orthographic_box_has_metric_extent_and_exact_depth():
    camera = Camera((H, W), subtype="orthographic", ortho_scale=0.2)  # 5 m wide view
    pose = np.eye(4)
    pose[:3, 3] = [0.5, 0.25, -4.0]
    frame = render_frame([cube_mesh(pose)], camera, np.eye(4))
    drawn = frame.depth > 0
    rows, cols = np.nonzero(drawn)
    s = W * 0.2  # 16 px per meter: the 1 m cube is 16 x 16 px
    assert drawn.sum() == 16 * 16
    assert cols.min() == math.ceil(camera.cx + s * 0.0 - 0.5)
    assert rows.min() == math.ceil(camera.cy - s * 0.75 - 0.5)
    np.testing.assert_allclose(frame.depth[drawn], 3.5, rtol=1e-6)  # front face at z = -3.5


def test_nearer_surface_wins_regardless_of_draw_order():
    camera = Camera((H, W))
    near_quad = quad(-0.5, 0.5, -0.5, 0.5, -2.0, semantic_id=1)
    far_quad = quad(-5, 5, -5, 5, -4.0, semantic_id=2)
    for meshes in ([near_quad, far_quad], [far_quad, near_quad]):
        frame = render_frame(meshes, camera, np.eye(4))
        assert frame.ids[H // 2, W // 2] == 1
        assert frame.depth[H // 2, W // 2] == pytest.approx(2.0, rel=1e-6)
        assert frame.ids[2, 2] == 2


def test_camera_pose_moves_the_view():
    camera = Camera((H, W))
    pose = np.eye(4)
    pose[:3, 3] = [0.0, 0.0, 1.5]  # camera 1.5 m back: the plane at z = -2 is 3.5 m away
    frame = render_frame([quad(-50, 50, -50, 50, -2.0)], camera, pose)
    np.testing.assert_allclose(frame.depth, 3.5, rtol=1e-6)


def test_degenerate_and_empty_meshes_draw_nothing_and_do_not_fail():
    camera = Camera((H, W))
    collinear = RenderMesh(
        np.array([[0, 0, -2.0], [1, 1, -2.0], [2, 2, -2.0]]), np.array([[0, 1, 2]])
    )
    repeated = RenderMesh(np.array([[0, 0, -2.0], [1, 0, -2.0]]), np.array([[0, 0, 1]]))
    empty = RenderMesh(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64))
    edge_on = RenderMesh(
        np.array([[0, -1, -1.0], [0, 1, -1.0], [0, 0, -3.0]]), np.array([[0, 1, 2]])
    )
    frame = render_frame([collinear, repeated, empty, edge_on], camera, np.eye(4))
    assert not frame.depth.any()


def test_huge_plane_far_beyond_the_screen_keeps_exact_depth():
    camera = Camera((H, W), hfov=90.0, far=1e7)
    frame = render_frame([quad(-1e6, 1e6, -1e6, 1e6, -5.0)], camera, np.eye(4))
    np.testing.assert_allclose(frame.depth, 5.0, rtol=1e-6)


def test_vertex_exactly_on_the_near_plane_is_kept():
    camera = Camera((H, W), hfov=90.0, near=0.5)
    vertices = np.array([[-1.0, -1.0, -0.5], [1.0, -1.0, -3.0], [0.0, 1.0, -3.0]])
    frame = render_frame([RenderMesh(vertices, np.array([[0, 1, 2]]))], camera, np.eye(4))
    assert frame.depth.any()
    assert frame.depth[frame.depth > 0].min() >= 0.5 * (1 - 1e-6)


def test_camera_inside_a_closed_box_sees_its_walls_at_the_right_depth():
    camera = Camera((H, W), hfov=90.0)
    pose = np.eye(4)
    pose[:3, :3] *= 4.0  # the cube [-0.5, 0.5]^3 scaled to [-2, 2]^3 around the camera
    frame = render_frame([cube_mesh(pose)], camera, np.eye(4))
    # every pixel sees a wall; the center pixel sees the wall z = -2 at z-depth 2
    assert np.all(frame.depth > 0)
    assert frame.depth[H // 2, W // 2] == pytest.approx(2.0, rel=1e-6)
    assert frame.depth.max() <= 2.0 * (1 + 1e-6)  # no wall is farther along the axis


def _screen(*corners: tuple[float, float]) -> np.ndarray:
    """``(3, 2, 1)`` corner pixel coordinates of one triangle."""
    return np.array(corners, dtype=np.float64)[:, :, None]


def test_the_bounding_box_pretest_keeps_every_triangle_that_covers_a_pixel_center():
    # pixel centers sit at (col + 1/2, row + 1/2). Each triangle below contains a center,
    # so the conservative pre-test must keep it: a sliver around center (0.5, 0.5) of the
    # top-left pixel, and a triangle around (10.5, 90.5) at the bottom of a tall 20 x 100
    # image (its rows lie beyond the image width: x and y must not be mixed up)
    top_left = _screen((0.1, 0.4), (0.9, 0.4), (0.5, 0.9))
    bottom = _screen((9.0, 89.0), (12.0, 89.0), (10.5, 93.0))
    for screen in (top_left, bottom):
        assert raster.bounding_box_has_pixel_centers(screen, 100, 20)[0]
        assert len(raster.scanline_spans(screen, 100, 20).row) > 0  # it does cover one
    # and one whose box holds no center (between rows 0 and 1 centers) is dropped
    between = _screen((2.0, 0.6), (4.0, 0.6), (3.0, 1.4))
    assert not raster.bounding_box_has_pixel_centers(between, 100, 20)[0]


def test_orthographic_depth_of_a_tilted_triangle_follows_its_plane():
    # corners (x, y, z) = (-1, -1, -2), (1, -1, -4), (0, 1, -3) lie on the plane z = -3 - x:
    # seen orthographically, the depth at a pixel center is 3 + x with x = (col + 1/2 - cx) / s
    camera = Camera((H, W), subtype="orthographic", ortho_scale=0.2)
    corners = np.array([[-1.0, -1.0, -2.0], [1.0, -1.0, -4.0], [0.0, 1.0, -3.0]])
    mesh = RenderMesh(corners, np.array([[0, 1, 2]]), base_color=(1, 2, 3))
    frame = render_frame([mesh], camera, np.eye(4))
    rows, cols = np.nonzero(frame.depth > 0)
    assert len(rows) > 50
    x = (cols + 0.5 - camera.cx) / camera.fx
    np.testing.assert_allclose(frame.depth[rows, cols], 3.0 + x, rtol=1e-6)
