"""The demo apartment: a two-room stage laid out for Habitat's rigid-object tutorial.

The managed rigid object tutorial was written for Habitat's ``apartment_1`` scan; its
coordinates assume a floor at ``y = -1.45`` m, a coffee table near ``(x 2.45, z 0.1)``
whose top is near ``y = -1.05`` (a sphere is dropped on it from ``(2.5, 0, 0.2)``, cereal
boxes float above it at ``x = 2.39``), an agent at ``(-0.15, -0.7, 1.0)`` looking towards
``+x`` (yaw -67.5 deg) and a robot starting on clear floor at ``(1.75, 0.4)`` that drives
forward (its ``-Z``, i.e. towards ``+x``) while turning left. This stage reproduces that
layout with boxes and lathes, in world coordinates (Y up, -Z forward, meters):

- main room ``x in [-1, 5]``, ``z in [-3.5, 2.5]``, floor ``y = -1.45``, ceiling ``1.3``;
- coffee table ``x in [2.25, 2.85]``, ``z in [-0.4, 0.5]``, top at ``y = -1.05``, on a rug;
- dark L-shaped sofa behind it (``x >= 3.45`` and ``z <= -1.0``), facing the camera;
- TV cabinet on the right wall, bookshelf and chair near the left wall, plant, lamp;
- a doorway in the far wall (``x = 5``, ``z in [1.2, 2.1]``) to a second room
  ``x in [5.1, 8.5]``, ``z in [-1.0, 2.5]`` with a two-step platform (0.15 m risers);
- ceiling light panels, windows with blinds on the left wall, a painting.

The floor within 1 m of ``(1.75, 0.4)`` is clear except for the table. The ceiling is a
single downward-facing plane so a navmesh builder finds no walkable roof. The stage is
drawn unlit, so its vertex colors carry a baked directional light (``bake``).
"""

from __future__ import annotations

import numpy as np

from engine.demo.geometry import (
    Part,
    bake,
    box,
    cylinder,
    horizontal_quad,
    lathe_part,
    merge_parts,
    quad,
)
from engine.scene.primitives import icosphere_solid

FLOOR_Y = -1.45  # top of the floor, meters
CEILING_Y = 1.3  # underside of the ceiling (2.75 m rooms)
TABLE_TOP_Y = -1.05  # coffee-table top surface
TABLE_X = (2.25, 2.85)
TABLE_Z = (-0.4, 0.5)
MAIN_ROOM = ((-1.0, 5.0), (-3.5, 2.5))  # (x range, z range), interior
SECOND_ROOM = ((5.1, 8.5), (-1.0, 2.5))
DOORWAY_Z = (1.2, 2.1)
DOOR_TOP_Y = FLOOR_Y + 2.1
STEP_RISER = 0.15
WALL_THICKNESS = 0.1
RUG = ((1.9, 3.3), (-0.8, 0.9))
RUG_BORDER = 0.12

WALL_COLOR = (232, 226, 214)
WOOD_TEXTURE_SIZE = 512
WOOD_TEXTURE_METERS = 9.6  # the floor texture spans a 9.6 m square (about 1.9 cm per texel)


def apartment_parts() -> list[Part]:
    """Every part of the apartment stage, in a fixed order (deterministic output)."""
    parts = floor_parts()
    parts.append(merge_parts(wall_parts(), name="walls"))
    parts += ceiling_parts()
    furniture = table_parts() + sofa_parts() + cabinet_parts() + decor_parts()
    furniture += second_room_parts()
    parts.append(merge_parts([bake(p) for p in furniture], name="furniture"))
    return parts


# ----------------------------------------------------------------------------------------
# Floor: a T-junction-free grid of flat quads (wood texture, rug colors) at FLOOR_Y
# ----------------------------------------------------------------------------------------


def floor_parts() -> list[Part]:
    """Floor of both rooms and the doorway, as one textured part plus the rug."""
    regions = [MAIN_ROOM, SECOND_ROOM, ((MAIN_ROOM[0][1], SECOND_ROOM[0][0]), DOORWAY_Z)]
    rug_inner = (
        (RUG[0][0] + RUG_BORDER, RUG[0][1] - RUG_BORDER),
        (RUG[1][0] + RUG_BORDER, RUG[1][1] - RUG_BORDER),
    )
    rects = regions + [RUG, rug_inner]
    xs = np.unique(np.concatenate([r[0] for r in rects]))  # every x cut of every rectangle
    zs = np.unique(np.concatenate([r[1] for r in rects]))
    wood, rug = [], []
    for x0, x1 in zip(xs[:-1], xs[1:], strict=True):
        for z0, z1 in zip(zs[:-1], zs[1:], strict=True):
            center = (0.5 * (x0 + x1), 0.5 * (z0 + z1))
            if not any(_inside(center, r) for r in regions):
                continue
            if _inside(center, rug_inner):
                rug.append(horizontal_quad(x0, x1, z0, z1, FLOOR_Y, (196, 176, 136)))
            elif _inside(center, RUG):
                rug.append(horizontal_quad(x0, x1, z0, z1, FLOOR_Y, (128, 42, 40)))
            else:
                wood.append(horizontal_quad(x0, x1, z0, z1, FLOOR_Y, (255, 255, 255)))
    floor = merge_parts(wood, name="floor")
    origin = np.array([MAIN_ROOM[0][0], MAIN_ROOM[1][0]])
    # u = (x - x_min) / S, v = (z - z_min) / S: the texture is laid flat over the rooms.
    floor.uvs = ((floor.vertices[:, [0, 2]] - origin) / WOOD_TEXTURE_METERS).astype(np.float32)
    floor.texture = wood_texture(WOOD_TEXTURE_SIZE)
    floor.colors = None
    return [floor, merge_parts(rug, name="rug")]


def _inside(point: tuple[float, float], rect: tuple) -> bool:
    (x0, x1), (z0, z1) = rect
    return x0 < point[0] < x1 and z0 < point[1] < z1


def wood_texture(size: int) -> np.ndarray:
    """Procedural oak planks ``(size, size, 3)`` uint8: rows of planks along the image's
    horizontal axis, staggered joints, per-plank tint and fine grain (deterministic)."""
    rng = np.random.default_rng(20240611)
    plank_px = max(4, size // 48)  # about 0.2 m planks
    rows = np.arange(size)[:, None]
    cols = np.arange(size)[None, :]
    plank_row = rows // plank_px
    n_rows = size // plank_px + 1
    offsets = rng.integers(0, size, n_rows)
    plank_length = size // 5
    plank_id = (cols + offsets[plank_row]) // plank_length + plank_row * 100
    tint = rng.uniform(0.82, 1.08, plank_id.max() + 1)[plank_id]
    grain = 0.06 * np.sin(cols * 0.35 + 3.0 * np.sin(rows * 0.9 + plank_row * 1.7))
    base = np.array([168.0, 122.0, 78.0])
    image = base * (tint + grain)[..., None]
    seam = ((rows % plank_px) == 0) | (((cols + offsets[plank_row]) % plank_length) == 0)
    image[seam] *= 0.55  # dark gaps between planks
    return np.clip(np.round(image), 0, 255).astype(np.uint8)


# ----------------------------------------------------------------------------------------
# Walls, doorway, ceiling, lights
# ----------------------------------------------------------------------------------------


def wall_parts() -> list[Part]:
    """Wall boxes (baked light) around both rooms, the doorway lintel and baseboards."""
    t, bottom, top = WALL_THICKNESS, FLOOR_Y - 0.05, CEILING_Y
    (mx0, mx1), (mz0, mz1) = MAIN_ROOM
    (sx0, sx1), (sz0, sz1) = SECOND_ROOM
    (dz0, dz1) = DOORWAY_Z
    boxes = [
        ((mx0 - t, bottom, mz0 - t), (mx1 + t, top, mz0)),  # left wall (windows)
        ((mx0 - t, bottom, mz1), (sx1 + t, top, mz1 + t)),  # right wall, both rooms
        ((mx0 - t, bottom, mz0 - t), (mx0, top, mz1 + t)),  # back wall behind the agent
        ((mx1, bottom, mz0 - t), (sx0, top, dz0)),  # partition, left of the door
        ((mx1, bottom, dz1), (sx0, top, mz1)),  # partition, right of the door
        ((mx1, DOOR_TOP_Y, dz0), (sx0, top, dz1)),  # lintel
        ((sx0, bottom, sz0 - t), (sx1 + t, top, sz0)),  # second room, left wall
        ((sx1, bottom, sz0 - t), (sx1 + t, top, sz1 + t)),  # second room, end wall
    ]
    parts = [box(lo, hi, WALL_COLOR, bake_light=True, name="wall") for lo, hi in boxes]
    trim = (92, 78, 64)
    frame = [
        ((mx1 - 0.03, FLOOR_Y, dz0 - 0.08), (sx0 + 0.03, DOOR_TOP_Y + 0.08, dz0)),
        ((mx1 - 0.03, FLOOR_Y, dz1), (sx0 + 0.03, DOOR_TOP_Y + 0.08, dz1 + 0.08)),
        ((mx1 - 0.03, DOOR_TOP_Y, dz0 - 0.08), (sx0 + 0.03, DOOR_TOP_Y + 0.08, dz1 + 0.08)),
    ]
    parts += [box(lo, hi, trim, bake_light=True, name="door_frame") for lo, hi in frame]
    parts += baseboards(trim)
    return parts


def baseboards(color: tuple[int, int, int]) -> list[Part]:
    """10 cm skirting boards along the main room's walls (gap left at the doorway)."""
    (x0, x1), (z0, z1) = MAIN_ROOM
    h, d, y0 = 0.1, 0.015, FLOOR_Y
    runs = [
        ((x0, y0, z0), (x1, y0 + h, z0 + d)),
        ((x0, y0, z1 - d), (x1, y0 + h, z1)),
        ((x0, y0, z0 + d), (x0 + d, y0 + h, z1 - d)),
        ((x1 - d, y0, z0 + d), (x1, y0 + h, DOORWAY_Z[0] - 0.08)),
        ((x1 - d, y0, DOORWAY_Z[1] + 0.08), (x1, y0 + h, z1 - d)),
    ]
    return [box(lo, hi, color, bake_light=True, name="baseboard") for lo, hi in runs]


def ceiling_parts() -> list[Part]:
    """Downward-facing ceiling planes (no walkable roof) and bright light panels."""
    grey = (236, 236, 232)
    planes = [
        horizontal_quad(*MAIN_ROOM[0], *MAIN_ROOM[1], CEILING_Y, grey, up=False),
        horizontal_quad(*SECOND_ROOM[0], *SECOND_ROOM[1], CEILING_Y, grey, up=False),
        horizontal_quad(MAIN_ROOM[0][1], SECOND_ROOM[0][0], *DOORWAY_Z, CEILING_Y, grey, False),
    ]
    ceiling = bake(merge_parts(planes, name="ceiling"))
    panel_y = CEILING_Y - 0.01
    centers = [(0.6, -1.6), (2.6, -1.6), (2.6, 1.1), (0.6, 1.1), (4.2, -0.3), (6.8, 0.8)]
    panels = [
        horizontal_quad(x - 0.6, x + 0.6, z - 0.3, z + 0.3, panel_y, (255, 255, 250), up=False)
        for x, z in centers
    ]
    return [ceiling, merge_parts(panels, name="lights")]


# ----------------------------------------------------------------------------------------
# Furniture
# ----------------------------------------------------------------------------------------


def table_parts() -> list[Part]:
    """Coffee table: 0.6 x 0.9 m walnut top at TABLE_TOP_Y, four legs, a lower shelf."""
    (x0, x1), (z0, z1) = TABLE_X, TABLE_Z
    top = box((x0, TABLE_TOP_Y - 0.05, z0), (x1, TABLE_TOP_Y, z1), (96, 64, 40), name="table")
    legs = [
        box((x, FLOOR_Y, z), (x + 0.05, TABLE_TOP_Y - 0.05, z + 0.05), (52, 40, 30), name="leg")
        for x in (x0 + 0.02, x1 - 0.07)
        for z in (z0 + 0.02, z1 - 0.07)
    ]
    shelf = box((x0 + 0.02, FLOOR_Y + 0.1, z0 + 0.02), (x1 - 0.02, FLOOR_Y + 0.13, z1 - 0.02),
                (80, 56, 38), name="shelf")  # fmt: skip
    return [top, shelf] + legs


def sofa_parts() -> list[Part]:
    """Dark L-shaped sofa: a long section along z at x >= 3.45 facing -x, and a short
    section along x at z <= -1.0 facing +z; seats at floor + 0.42 m, backs to + 0.85 m."""
    body, cushion = (52, 55, 68), (70, 74, 90)
    seat, back = FLOOR_Y + 0.42, FLOOR_Y + 0.85
    parts = [
        box((3.45, FLOOR_Y, -1.9), (4.35, seat - 0.1, 0.9), body, name="sofa"),
        box((4.1, FLOOR_Y, -1.9), (4.35, back, 0.9), body, name="sofa_back"),
        box((3.45, FLOOR_Y, 0.9), (4.35, seat + 0.15, 1.1), body, name="sofa_arm"),
        box((2.0, FLOOR_Y, -1.9), (3.45, seat - 0.1, -1.0), body, name="sofa"),
        box((2.0, FLOOR_Y, -1.9), (3.45, back, -1.65), body, name="sofa_back"),
        box((1.8, FLOOR_Y, -1.9), (2.0, seat + 0.15, -1.0), body, name="sofa_arm"),
    ]
    for z0, z1 in ((-1.6, -0.75), (-0.73, 0.08), (0.1, 0.88)):
        parts.append(box((3.47, seat - 0.1, z0), (4.1, seat, z1), cushion, name="cushion"))
    for x0, x1 in ((2.02, 2.72), (2.74, 3.43)):
        parts.append(box((x0, seat - 0.1, -1.63), (x1, seat, -1.02), cushion, name="cushion"))
    pillows = [((3.95, -1.45), (180, 140, 60)), ((3.95, 0.6), (150, 62, 60)),
               ((2.4, -1.55), (150, 62, 60))]  # fmt: skip
    for (x, z), color in pillows:
        parts.append(box((x - 0.09, seat, z - 0.2), (x + 0.09, seat + 0.32, z + 0.2), color))
    return parts


def cabinet_parts() -> list[Part]:
    """TV cabinet with a TV on the right wall; bookshelf with books; a wooden chair."""
    z_wall = MAIN_ROOM[1][1]
    parts = [
        box((1.6, FLOOR_Y, z_wall - 0.45), (3.2, FLOOR_Y + 0.55, z_wall), (124, 92, 62)),
        box((1.85, FLOOR_Y + 0.85, z_wall - 0.06), (2.95, FLOOR_Y + 1.5, z_wall), (22, 22, 24)),
        quad(_screen_corners(z_wall - 0.065), (38, 52, 74), name="screen"),
    ]
    x0 = MAIN_ROOM[0][0]
    parts.append(box((x0, FLOOR_Y, -3.3), (x0 + 0.4, FLOOR_Y + 1.8, -2.0), (150, 118, 86)))
    book_colors = [(160, 50, 45), (45, 90, 150), (210, 180, 70), (60, 120, 70), (120, 60, 130)]
    for shelf in range(4):
        y = FLOOR_Y + 0.1 + 0.42 * shelf
        for k in range(5):
            z = -3.2 + 0.24 * k
            parts.append(box((x0 + 0.4, y, z), (x0 + 0.43, y + 0.3, z + 0.2),
                             book_colors[(k + shelf) % 5], name="book"))  # fmt: skip
    parts += chair_parts(0.55, -2.7)
    return parts


def _screen_corners(z: float) -> np.ndarray:
    """TV screen rectangle in the plane ``z``, counter-clockwise seen from -z."""
    y0, y1 = FLOOR_Y + 0.9, FLOOR_Y + 1.45
    return np.array([[1.9, y0, z], [1.9, y1, z], [2.9, y1, z], [2.9, y0, z]])


def chair_parts(x: float, z: float) -> list[Part]:
    """Wooden chair centered at ``(x, z)``: 0.45 m seat, back towards -z."""
    wood = (140, 100, 62)
    seat_y = FLOOR_Y + 0.45
    parts = [box((x - 0.22, seat_y - 0.04, z - 0.22), (x + 0.22, seat_y, z + 0.22), wood)]
    for dx in (-0.2, 0.16):
        for dz in (-0.2, 0.16):
            lo = (x + dx, FLOOR_Y, z + dz)
            parts.append(box(lo, (lo[0] + 0.04, seat_y - 0.04, lo[2] + 0.04), wood, name="leg"))
    parts.append(box((x - 0.22, seat_y, z - 0.22), (x + 0.22, seat_y + 0.45, z - 0.18), wood))
    return parts


def decor_parts() -> list[Part]:
    """Plant, floor lamp, windows with blinds on the left wall, painting on the far wall."""
    parts = [
        lathe_part([0.0, 0.16, 0.2, 0.0], [0.0, 0.0, 0.45, 0.45], 20, (176, 92, 60),
                   center=(4.6, FLOOR_Y, 2.1), name="pot"),
        cylinder((4.7, FLOOR_Y + 0.8, -2.4), 0.015, 0.8, (40, 40, 40), segments=8, name="pole"),
        lathe_part([0.0, 0.24, 0.14, 0.0], [0.0, 0.0, 0.3, 0.3], 24, (236, 226, 200),
                   center=(4.7, FLOOR_Y + 1.45, -2.4), name="shade"),
        box((4.55, FLOOR_Y, -2.55), (4.85, FLOOR_Y + 0.03, -2.25), (40, 40, 40), name="base"),
    ]  # fmt: skip
    leaves, faces = icosphere_solid(2)
    colors = np.tile([58, 122, 56, 255], (len(leaves), 1)).astype(np.uint8)
    leaves = leaves * [0.38, 0.45, 0.38] + [4.6, FLOOR_Y + 0.85, 2.1]
    parts.append(Part(leaves, faces, colors=colors, name="foliage"))
    z_wall = MAIN_ROOM[1][0] + 0.005  # just in front of the left wall, facing +z
    for x0, x1 in ((0.4, 1.6), (2.2, 3.4)):
        parts.append(_wall_quad_z(x0, x1, -0.6, 0.6, z_wall, (150, 188, 222)))
        parts.append(box((x0 - 0.05, -0.65, z_wall - 0.005), (x1 + 0.05, -0.6, z_wall + 0.04),
                         (245, 245, 240), name="sill"))  # fmt: skip
        for k in range(8):  # horizontal blinds over the top half
            y = 0.55 - 0.075 * k
            parts.append(_wall_quad_z(x0, x1, y - 0.03, y, z_wall + 0.01, (214, 212, 204)))
    x_wall = MAIN_ROOM[0][1] - 0.005  # far wall, facing -x
    painting = [((-2.6, -1.3), (40, 60, 110)), ((-2.5, -1.9), (220, 170, 60)),
                ((-1.85, -1.4), (180, 70, 60))]  # fmt: skip
    for depth, ((z0, z1), color) in enumerate(painting):  # later layers sit 1 cm in front
        y0, y1 = (-0.45, 0.25) if depth == 0 else (-0.35, 0.15)
        parts.append(_wall_quad_x(z0, z1, y0, y1, x_wall - 0.01 * depth, color))
    return parts


def _wall_quad_z(x0: float, x1: float, y0: float, y1: float, z: float, color: tuple) -> Part:
    """Quad in the plane ``z`` facing +z (decals on the left wall)."""
    return quad(np.array([[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]]), color)


def _wall_quad_x(z0: float, z1: float, y0: float, y1: float, x: float, color: tuple) -> Part:
    """Quad in the plane ``x`` facing -x (decals on the far wall)."""
    return quad(np.array([[x, y0, z0], [x, y0, z1], [x, y1, z1], [x, y1, z0]]), color)


def second_room_parts() -> list[Part]:
    """Second room: a two-step platform (0.15 m risers) on the end wall and a desk."""
    (x0, x1), (z0, z1) = SECOND_ROOM
    step = (132, 132, 142)
    parts = [
        box((x1 - 1.5, FLOOR_Y, z0), (x1, FLOOR_Y + STEP_RISER, z1), step, name="step_1"),
        box((x1 - 0.9, FLOOR_Y, z0), (x1, FLOOR_Y + 2 * STEP_RISER, z1), step, name="step_2"),
        box((x0 + 0.6, FLOOR_Y + 0.72, z0 + 0.05), (x0 + 1.8, FLOOR_Y + 0.76, z0 + 0.75),
            (164, 132, 92), name="desk"),
    ]  # fmt: skip
    for dx in (0.62, 1.74):
        parts.append(box((x0 + dx, FLOOR_Y, z0 + 0.08), (x0 + dx + 0.04, FLOOR_Y + 0.72, z0 + 0.72),
                         (90, 70, 50), name="desk_leg"))  # fmt: skip
    return parts
