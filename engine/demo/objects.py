"""Demo objects for the tutorial: sphere, cereal box, chef can, clamp and a small robot.

Each builder returns the object's parts (see ``engine.demo.geometry``) in the object's own
frame, plus the fields of its ``*.object_config.json``. Sizes and masses follow the YCB
objects Habitat's tutorial uses (cracker box 0.16 x 0.06 x 0.21 m and 0.411 kg, master chef
can 0.102 m x 0.14 m and 0.414 kg, large clamp 0.125 kg).

Frames, as in Habitat's data:

- The YCB stand-ins (``cheezit``, ``chefcan``, ``largeclamp``) keep YCB's **Z-up** object
  frame and their configs do not convert it, exactly like Habitat's example objects: a
  cereal box added without rotation lies on its back, and the tutorial stands it up with
  a 90 degree rotation about -X (local +Z becomes world +Y). Its printed front is the -Y
  face (world +Z after that rotation, towards the tutorial's camera).
- ``banana`` and ``mug`` are extra YCB-like objects in the same Z-up convention.
- ``sphere`` is a red icosphere of radius 0.25 m centered at its origin.
- ``locobot_merged`` is Y-up with its forward (camera) along -Z, centered on the Y axis.
  In its mesh the lowest points of the wheels and casters are at ``y = 0`` and the camera
  head tops out at 0.56 m. The config sets ``COM = [0, 0, 0]``: the center of mass is on
  the axis, at the bottom of the base, like Habitat's locobot, so the robot's translation is
  the point it stands on: a navmesh point (floor height) puts its wheels on the floor. The
  tutorial's first-person camera, 0.6 m above the translation, sits just above the head.
"""

from __future__ import annotations

import numpy as np

from engine.demo.geometry import Part, box, cylinder, lathe_part, merge_parts, tube
from engine.scene.primitives import icosphere_solid

CHEEZIT_SIZE = (0.16, 0.06, 0.21)  # x, y (thickness), z (height, YCB up) in meters
CHEF_CAN_RADIUS = 0.051
CHEF_CAN_HEIGHT = 0.14
SPHERE_RADIUS = 0.25
LOCOBOT_RADIUS = 0.175
LOCOBOT_COM_HEIGHT = 0.0  # COM at the wheels' floor contact: translation = footprint


def sphere_object() -> tuple[list[Part], dict]:
    """Red sphere of radius 0.25 m (icosphere, 1280 triangles), mass 1 kg."""
    vertices, faces = icosphere_solid(3)
    colors = np.tile([220, 28, 28, 255], (len(vertices), 1)).astype(np.uint8)
    part = Part(vertices * SPHERE_RADIUS, faces, colors=colors, name="sphere")
    config = {"render_asset": "sphere.glb", "collision_asset": "sphere.glb", "mass": 1.0}
    return [part], config


def cheezit_object() -> tuple[list[Part], dict]:
    """Cereal box 0.16 x 0.06 x 0.21 m (Z-up) with a printed texture atlas, 0.411 kg."""
    size = np.array(CHEEZIT_SIZE)
    part = box(-0.5 * size, 0.5 * size, (255, 255, 255), name="cheezit")
    part.uvs = _cheezit_uvs(part.vertices, size)
    part.texture = cheezit_texture()
    part.colors = None
    config = {"render_asset": "cheezit.glb", "mass": 0.411, "friction_coefficient": 0.5}
    return [part], config


# Atlas cells (column, row) of a 2 x 2 texture: row 0 is the top half of the image.
_CELL_OF_FACE = {"-y": (0, 0), "+y": (1, 0), "x": (0, 1), "z": (1, 1)}


def _cheezit_uvs(vertices: np.ndarray, size: np.ndarray) -> np.ndarray:
    """UVs of the 24 box vertices: each side maps to its atlas cell, upright from outside.

    Faces come in box_geometry's order (+X, -X, +Y, -Y, +Z, -Z, 4 vertices each). For a
    side, ``s`` runs left to right as seen from outside and ``t`` upwards (+Z), both in
    [0, 1]; the cell ``(c, r)`` maps them to ``u = (c + s) / 2``, ``v = (1 - r + t) / 2``.
    """
    rel = vertices / size + 0.5  # each coordinate in [0, 1]
    uvs = np.zeros((len(vertices), 2))
    for k, (key, s_of, t_of) in enumerate([
        ("x", lambda p: p[:, 1], lambda p: p[:, 2]),  # +X: viewer's right is +y
        ("x", lambda p: 1 - p[:, 1], lambda p: p[:, 2]),  # -X: right is -y
        ("+y", lambda p: 1 - p[:, 0], lambda p: p[:, 2]),  # +Y (back): right is -x
        ("-y", lambda p: p[:, 0], lambda p: p[:, 2]),  # -Y (front): right is +x
        ("z", lambda p: p[:, 0], lambda p: p[:, 1]),  # +Z top
        ("z", lambda p: p[:, 0], lambda p: 1 - p[:, 1]),  # -Z bottom
    ]):  # fmt: skip
        rows = slice(4 * k, 4 * k + 4)
        col, row = _CELL_OF_FACE[key]
        inset = 0.02  # keep samples away from the neighbouring cell
        s = inset + (1 - 2 * inset) * s_of(rel[rows])
        t = inset + (1 - 2 * inset) * t_of(rel[rows])
        uvs[rows] = np.stack([(col + s) / 2.0, (1 - row + t) / 2.0], axis=1)
    return uvs.astype(np.float32)


def cheezit_texture(cell: int = 128) -> np.ndarray:
    """``(2 cell, 2 cell, 3)`` uint8 atlas: printed front, back panel, sides, top."""
    red, yellow, orange, white = (200, 32, 30), (250, 210, 40), (235, 140, 40), (245, 245, 240)
    atlas = np.empty((2 * cell, 2 * cell, 3), dtype=np.uint8)
    atlas[:] = red
    i, j = np.mgrid[0:cell, 0:cell] / cell  # row (0 = top), column in [0, 1)
    front = atlas[:cell, :cell]
    front[((j - 0.5) / 0.42) ** 2 + ((i - 0.28) / 0.16) ** 2 < 1.0] = yellow  # logo
    front[(np.abs(i - 0.28) < 0.04) & (np.abs(j - 0.5) < 0.3)] = red  # "lettering"
    crackers = (i > 0.55) & (i < 0.92) & (j > 0.1) & (j < 0.9)
    tile = ((i * 9).astype(int) + (j * 9).astype(int)) % 2 == 0
    front[crackers & tile] = orange
    front[crackers & ~tile] = (215, 120, 30)
    back = atlas[:cell, cell:]
    back[(i > 0.15) & (i < 0.85) & (j > 0.15) & (j < 0.85)] = white
    back[(i > 0.2) & (i < 0.8) & (j > 0.2) & (j < 0.8) & ((i * 40).astype(int) % 3 == 0)] = 90
    side = atlas[cell:, :cell]
    side[(j > 0.3) & (j < 0.7)] = yellow
    top = atlas[cell:, cell:]
    top[(i > 0.35) & (i < 0.65)] = yellow
    return atlas


def chefcan_object() -> tuple[list[Part], dict]:
    """Blue coffee can (radius 0.051 m, height 0.14 m, axis +Z) with a gold band, 0.414 kg."""
    r, h = CHEF_CAN_RADIUS, 0.5 * CHEF_CAN_HEIGHT
    blue, gold, metal = (35, 75, 160), (235, 195, 60), (190, 190, 196)
    bands = [  # (radii, heights along the axis, color), bottom to top along the outside
        ([0.0, r], [-h, -h], metal),
        ([r, r], [-h, -0.025], blue),
        ([r, r], [-0.025, 0.03], gold),
        ([r, r], [0.03, h], blue),
        ([r, 0.0], [h, h], metal),
    ]
    parts = [lathe_part(rad, hei, 32, color, axis="z", name="can") for rad, hei, color in bands]
    config = {"render_asset": "chefcan.glb", "mass": 0.414, "friction_coefficient": 0.5}
    return [merge_parts(parts, name="chefcan")], config


def largeclamp_object() -> tuple[list[Part], dict]:
    """Orange and black F-clamp lying in the XY plane (Z-up, 4 cm thick), 0.125 kg.

    Separate meshes (bar, two jaws, handle) give a compound of convex hulls."""
    black, orange = (28, 28, 30), (235, 110, 20)
    parts = [
        box((-0.1, 0.04, -0.008), (0.1, 0.056, 0.008), black, name="bar"),
        box((0.075, -0.06, -0.015), (0.1, 0.04, 0.015), orange, name="fixed_jaw"),
        box((-0.02, -0.06, -0.015), (0.005, 0.04, 0.015), orange, name="sliding_jaw"),
        box((-0.03, -0.13, -0.02), (0.015, -0.06, 0.02), black, name="handle"),
    ]
    config = {"render_asset": "largeclamp.glb", "mass": 0.125, "friction_coefficient": 0.6}
    return parts, config


def banana_object() -> tuple[list[Part], dict]:
    """Yellow banana lying in the XY plane (Z-up): a tapered tube on a 100 degree arc of
    radius 0.11 m (about 0.19 m long, 0.036 m thick), brown tips, 0.066 kg."""
    angle = np.linspace(np.radians(-50.0), np.radians(50.0), 24)
    spine = np.stack([0.11 * np.sin(angle), -0.11 * np.cos(angle), np.zeros_like(angle)], 1)
    s = np.linspace(0.0, 1.0, len(angle))  # arc-length fraction along the banana
    radii = 0.004 + 0.014 * np.sin(np.pi * s) ** 0.6  # thick middle, thin tips
    body = tube(spine, radii, (0.0, 0.0, 1.0), 12, (232, 200, 52), name="banana")
    tips = body.vertices[:, 0] ** 2 > (0.11 * np.sin(np.radians(44.0))) ** 2
    if body.colors is None:  # tube() always colors its vertices
        raise RuntimeError("the banana body has no vertex colors to paint its tips on")
    body.colors[tips] = (96, 70, 36, 255)
    config = {"render_asset": "banana.glb", "mass": 0.066, "friction_coefficient": 0.5}
    return [body], config


def mug_object() -> tuple[list[Part], dict]:
    """Red mug (Z-up): open cylinder of radius 0.04 m, height 0.08 m, 4 mm wall, with a
    handle on +X; 0.118 kg. Separate meshes (cup, handle) give two convex hulls."""
    r, h, wall = 0.04, 0.04, 0.004
    red = (196, 58, 48)
    # Profile along the outside then the inside: bottom center, outer wall, rim, inner
    # wall down to the inner floor (radius 0 ends are poles).
    radii = [0.0, r, r, r - wall, r - wall, 0.0]
    heights = [-h, -h, h, h, -h + wall, -h + wall]
    cup = lathe_part(radii, heights, 32, red, axis="z", name="cup")
    angle = np.linspace(-0.5 * np.pi, 0.5 * np.pi, 12)
    spine = np.stack([r + 0.022 * np.cos(angle), np.zeros_like(angle), 0.024 * np.sin(angle)], 1)
    handle = tube(spine, np.full(len(angle), 0.006), (0.0, 1.0, 0.0), 10, red, name="handle")
    config = {"render_asset": "mug.glb", "mass": 0.118, "friction_coefficient": 0.5}
    return [cup, handle], config


def locobot_object() -> tuple[list[Part], dict]:
    """Small wheeled robot, 0.35 m across and 0.56 m tall, COM at the bottom of its base."""
    dark, black, grey, metal = (46, 46, 52), (24, 24, 26), (120, 120, 126), (172, 172, 178)
    parts = [
        cylinder((0.0, 0.075, 0.0), LOCOBOT_RADIUS, 0.045, dark, segments=32, name="base"),
        cylinder((0.0, 0.065, 0.0), LOCOBOT_RADIUS + 0.003, 0.012, grey, segments=32),
        cylinder((0.0, 0.2075, 0.0), 0.16, 0.0075, black, segments=32, name="deck"),
        box((-0.02, 0.215, 0.03), (0.02, 0.5, 0.07), metal, name="mast"),
        box((-0.07, 0.5, -0.03), (0.07, 0.56, 0.05), dark, name="head"),
    ]
    for x in (-0.13, 0.13):  # drive wheels: radius 0.05 about the x axis, touching y = 0
        parts.append(cylinder((x, 0.05, 0.0), 0.05, 0.012, black, segments=24, axis="x"))
    for z in (-0.13, 0.13):  # casters: spheres of radius 0.015 touching y = 0
        vertices, faces = icosphere_solid(1)
        colors = np.tile([*grey, 255], (len(vertices), 1)).astype(np.uint8)
        parts.append(Part(vertices * 0.015 + [0.0, 0.015, z], faces, colors=colors))
    for x in (-0.1, 0.1):
        for z in (-0.1, 0.1):  # deck standoffs
            parts.append(cylinder((x, 0.16, z), 0.008, 0.04, metal, segments=8))
    for x in (-0.035, 0.035):  # stereo camera lenses looking along -Z
        parts.append(cylinder((x, 0.53, -0.038), 0.016, 0.008, black, segments=16, axis="z"))
    config = {
        "render_asset": "locobot_merged.glb",
        "mass": 4.0,
        "COM": [0.0, LOCOBOT_COM_HEIGHT, 0.0],
        "join_collision_meshes": True,
        "friction_coefficient": 0.5,
    }
    return [merge_parts(parts, name="locobot")], config
