"""Habitat's 12 built-in primitive assets, as plain triangle meshes.

Habitat-sim registers one primitive asset template per Magnum primitive (cube, icosphere,
UV sphere, cylinder, cone, capsule; each "Solid" and "Wireframe") and names it by a handle
that spells its construction parameters, e.g.
``cylinderSolid_rings_1_segments_12_halfLen_1_useTexCoords_false_useTangents_false_capEnds_true``.
This module parses such handles and builds the matching unit mesh:

- ``cube``: the box ``[-1, 1]^3`` (side 2).
- ``icosphere``: an icosahedron with every triangle split in 4, ``subdivs`` times, the new
  vertices pushed out to the unit sphere (radius 1, 20 * 4^subdivs triangles).
- ``uvSphere``: radius 1, ``rings`` latitude bands and ``segments`` longitude slices.
- ``cylinder``: radius 1 around +Y, ``y`` in ``[-halfLen, halfLen]``, ``rings`` bands along
  the axis, end caps when ``capEnds``.
- ``cone``: base radius 1 at ``y = -halfLen``, apex at ``y = +halfLen``, base cap when
  ``capEnd``.
- ``capsule3D``: a cylinder of radius 1 and half length ``halfLen`` closed by two unit
  hemispheres (total height ``2 * halfLen + 2``).

Wireframe primitives are returned as the solid surface with the same parameters, so that
they still render and collide (rigidsim has no line renderer).

Every surface of revolution is a *lathe*: a 2-D profile ``(r_k, y_k)`` swept around the Y
axis, ``p(k, j) = (r_k sin(phi_j), y_k, r_k cos(phi_j))`` with ``phi_j = 2 pi j / segments``.
Profiles run from the bottom to the top along the outside of the solid, so every triangle
is counter-clockwise seen from outside (outward normals, positive signed volume).

Conventions: Y up, meters, ``vertices (V, 3) float64``, ``faces (F, 3) int64``.
Reference: Magnum ``Primitives`` (mosra/magnum, MIT) and Habitat-sim
``PrimitiveAssetAttributes`` (MIT) for the handle grammar and default parameters.
"""

from __future__ import annotations

import numpy as np

# Handle prefix -> (shape kind, parameter names in handle order). Solid handles also end
# with flags (useTexCoords, useTangents, capEnd(s)) that do not change the geometry except
# the caps.
_HANDLE_GRAMMAR: dict[str, tuple[str, tuple[str, ...]]] = {
    "capsule3DSolid": (
        "capsule",
        ("hemiRings", "cylRings", "segments", "halfLen", "useTexCoords", "useTangents"),
    ),
    "capsule3DWireframe": ("capsule", ("hemiRings", "cylRings", "segments", "halfLen")),
    "coneSolid": (
        "cone",
        ("segments", "halfLen", "rings", "useTexCoords", "useTangents", "capEnd"),
    ),
    "coneWireframe": ("cone", ("segments", "halfLen")),
    "cubeSolid": ("cube", ()),
    "cubeWireframe": ("cube", ()),
    "cylinderSolid": (
        "cylinder",
        ("rings", "segments", "halfLen", "useTexCoords", "useTangents", "capEnds"),
    ),
    "cylinderWireframe": ("cylinder", ("rings", "segments", "halfLen")),
    "icosphereSolid": ("icosphere", ("subdivs",)),
    "icosphereWireframe": ("icosphere", ("subdivs",)),
    "uvSphereSolid": ("uvSphere", ("rings", "segments", "useTexCoords", "useTangents")),
    "uvSphereWireframe": ("uvSphere", ("rings", "segments")),
}

#: The 12 default primitive asset handles Habitat-sim registers (sorted). Built from the
#: default parameters of Habitat-sim's primitive attributes constructors.
PRIMITIVE_ASSET_HANDLES: list[str] = sorted(
    [
        "capsule3DSolid_hemiRings_4_cylRings_1_segments_12_halfLen_0.75"
        "_useTexCoords_false_useTangents_false",
        "capsule3DWireframe_hemiRings_8_cylRings_1_segments_16_halfLen_1",
        "coneSolid_segments_12_halfLen_1.25_rings_1_useTexCoords_false_useTangents_false"
        "_capEnd_true",
        "coneWireframe_segments_32_halfLen_1.25",
        "cubeSolid",
        "cubeWireframe",
        "cylinderSolid_rings_1_segments_12_halfLen_1_useTexCoords_false_useTangents_false"
        "_capEnds_true",
        "cylinderWireframe_rings_1_segments_32_halfLen_1",
        "icosphereSolid_subdivs_1",
        "icosphereWireframe_subdivs_1",
        "uvSphereSolid_rings_8_segments_16_useTexCoords_false_useTangents_false",
        "uvSphereWireframe_rings_16_segments_32",
    ]
)

_BOOL_KEYS = ("useTexCoords", "useTangents", "capEnd", "capEnds")
_FLOAT_KEYS = ("halfLen",)
# Smallest legal value of each integer parameter (Magnum's preconditions).
_INT_MINIMUM = {"hemiRings": 1, "cylRings": 1, "segments": 3, "rings": 1, "subdivs": 0}
_MAX_SUBDIVS = 6  # 20 * 4^6 = 81920 triangles; more is surely a typo


def is_primitive_handle(handle: str) -> bool:
    """Return True if ``handle`` names a primitive asset (starts with a primitive prefix)."""
    if not isinstance(handle, str):
        return False
    name = handle.split("_", 1)[0]
    return name in _HANDLE_GRAMMAR


def parse_primitive_handle(handle: str) -> tuple[str, dict[str, float | int | bool]]:
    """Parse a primitive asset handle into its shape kind and parameters.

    Parameters
    ----------
    handle : str
        e.g. ``"cylinderSolid_rings_1_segments_12_halfLen_1_useTexCoords_false_..."``:
        a class prefix then ``_key_value`` pairs in the prefix's order.

    Returns
    -------
    kind : str
        One of ``cube, icosphere, uvSphere, cylinder, cone, capsule``.
    params : dict
        The parsed values (int, float or bool) plus ``"wireframe": bool``. Missing cap
        flags of wireframe handles default to True (closed surfaces).

    Raises
    ------
    ValueError
        If the prefix is unknown, a key is missing or misplaced, or a value is illegal.
    """
    if not isinstance(handle, str) or not is_primitive_handle(handle):
        raise ValueError(f"handle {handle!r} is not a primitive asset handle")
    prefix, _, rest = handle.partition("_")
    kind, keys = _HANDLE_GRAMMAR[prefix]
    tokens = rest.split("_") if rest else []
    if len(tokens) != 2 * len(keys) or tuple(tokens[0::2]) != keys:
        expected = "_".join(f"{key}_<value>" for key in keys)
        raise ValueError(f"handle {handle!r} must look like '{prefix}_{expected}'".rstrip("_"))
    params: dict[str, float | int | bool] = {"wireframe": prefix.endswith("Wireframe")}
    for key, text in zip(tokens[0::2], tokens[1::2], strict=True):
        params[key] = _parse_value(handle, key, text)
    params.setdefault("capEnd", True)
    params.setdefault("capEnds", True)
    if kind == "cone":
        params.setdefault("rings", 1)
    return kind, params


def _parse_value(handle: str, key: str, text: str) -> float | int | bool:
    """Convert one handle value and check Magnum's range for it."""
    if key in _BOOL_KEYS:
        if text not in ("true", "false"):
            raise ValueError(f"handle {handle!r}: {key} must be true or false, got {text!r}")
        return text == "true"
    try:
        value = float(text) if key in _FLOAT_KEYS else int(text)
    except ValueError:
        raise ValueError(f"handle {handle!r}: {key} value {text!r} is not a number") from None
    if key in _FLOAT_KEYS and not (np.isfinite(value) and value > 0.0):
        raise ValueError(f"handle {handle!r}: {key} must be a positive number, got {text!r}")
    if key in _INT_MINIMUM and value < _INT_MINIMUM[key]:
        raise ValueError(f"handle {handle!r}: {key} must be >= {_INT_MINIMUM[key]}, got {value}")
    if key == "subdivs" and value > _MAX_SUBDIVS:
        raise ValueError(f"handle {handle!r}: subdivs must be <= {_MAX_SUBDIVS}, got {value}")
    return value


def primitive_geometry(handle: str) -> tuple[np.ndarray, np.ndarray]:
    """Build the unit triangle mesh named by a primitive handle.

    Returns
    -------
    vertices : (V, 3) float64, meters, object frame (Y up)
    faces : (F, 3) int64, counter-clockwise seen from outside
    """
    kind, p = parse_primitive_handle(handle)
    if kind == "cube":
        return cube_solid()
    if kind == "icosphere":
        return icosphere_solid(int(p["subdivs"]))
    if kind == "uvSphere":
        if int(p["rings"]) < 2:
            raise ValueError(f"handle {handle!r}: rings must be >= 2 for a UV sphere")
        return uv_sphere_solid(int(p["rings"]), int(p["segments"]))
    if kind == "cylinder":
        return cylinder_solid(
            int(p["rings"]), int(p["segments"]), float(p["halfLen"]), bool(p["capEnds"])
        )
    if kind == "cone":
        return cone_solid(
            int(p["rings"]), int(p["segments"]), float(p["halfLen"]), bool(p["capEnd"])
        )
    return capsule_solid(
        int(p["hemiRings"]), int(p["cylRings"]), int(p["segments"]), float(p["halfLen"])
    )


# ----------------------------------------------------------------------------------------
# Shape builders
# ----------------------------------------------------------------------------------------


def cube_solid() -> tuple[np.ndarray, np.ndarray]:
    """The box ``[-1, 1]^3``: 6 faces x 4 own vertices (sharp edges), 12 triangles."""
    return box_geometry(np.zeros(3), np.full(3, 2.0))


def box_geometry(center: np.ndarray, size: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Axis-aligned box with 4 vertices per face (24 vertices, 12 CCW triangles).

    Face order: +X, -X, +Y, -Y, +Z, -Z; triangles ``2k, 2k + 1`` belong to face ``k``.
    """
    half = 0.5 * np.asarray(size, dtype=np.float64)
    vertices = []
    for axis in range(3):
        u_axis, v_axis = (axis + 1) % 3, (axis + 2) % 3
        for sign in (1.0, -1.0):
            # Corners (u, v) in CCW order seen from outside: for +axis, u x v = +axis.
            corners = [(-1, -1), (1, -1), (1, 1), (-1, 1)]
            if sign < 0:
                corners = corners[::-1]
            for cu, cv in corners:
                p = np.zeros(3)
                p[axis] = sign * half[axis]
                p[u_axis] = cu * half[u_axis]
                p[v_axis] = cv * half[v_axis]
                vertices.append(p)
    quad = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int64)
    faces = np.concatenate([quad + 4 * k for k in range(6)])
    return np.asarray(vertices) + np.asarray(center, dtype=np.float64), faces


def icosphere_solid(subdivisions: int) -> tuple[np.ndarray, np.ndarray]:
    """Unit icosphere: split each triangle into 4 and project the midpoints to the sphere."""
    t = (1.0 + 5.0**0.5) / 2.0  # golden ratio: icosahedron corners are (0, +-1, +-t) cycled
    vertices = [
        [-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0],
        [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
        [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1],
    ]  # fmt: skip
    faces = [
        [0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
        [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
        [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
        [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1],
    ]  # fmt: skip
    points = [np.asarray(v, dtype=np.float64) / np.linalg.norm(v) for v in vertices]
    for _ in range(subdivisions):
        faces = _split_triangles(points, faces)
    return np.asarray(points), np.asarray(faces, dtype=np.int64)


def _split_triangles(points: list[np.ndarray], faces: list[list[int]]) -> list[list[int]]:
    """One icosphere subdivision: 4 triangles per triangle, shared edge midpoints.

    ``points`` grows in place with the new unit-length midpoints ``(p_i + p_j) / |p_i + p_j|``.
    """
    midpoint_index: dict[tuple[int, int], int] = {}

    def midpoint(i: int, j: int) -> int:
        key = (min(i, j), max(i, j))
        if key not in midpoint_index:
            m = points[i] + points[j]
            points.append(m / np.linalg.norm(m))  # push out to the unit sphere
            midpoint_index[key] = len(points) - 1
        return midpoint_index[key]

    split = []
    for a, b, c in faces:
        ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
        split += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
    return split


def uv_sphere_solid(rings: int, segments: int) -> tuple[np.ndarray, np.ndarray]:
    """Unit UV sphere with ``rings`` latitude bands (poles are single vertices)."""
    theta = np.linspace(-0.5 * np.pi, 0.5 * np.pi, rings + 1)  # latitude, bottom to top
    radii = np.cos(theta)
    radii[[0, -1]] = 0.0  # exact poles
    return lathe(radii, np.sin(theta), segments)


def cylinder_solid(
    rings: int, segments: int, half_length: float, cap_ends: bool
) -> tuple[np.ndarray, np.ndarray]:
    """Unit-radius cylinder around +Y, ``y`` in ``[-half_length, half_length]``."""
    heights = np.linspace(-half_length, half_length, rings + 1)
    parts = [lathe(np.ones(rings + 1), heights, segments)]
    if cap_ends:
        parts.append(lathe(np.array([0.0, 1.0]), np.full(2, -half_length), segments))
        parts.append(lathe(np.array([1.0, 0.0]), np.full(2, half_length), segments))
    return concatenate_geometry(parts)


def cone_solid(
    rings: int, segments: int, half_length: float, cap_end: bool
) -> tuple[np.ndarray, np.ndarray]:
    """Cone with base radius 1 at ``y = -half_length`` and apex at ``y = +half_length``."""
    radii = np.linspace(1.0, 0.0, rings + 1)
    parts = [lathe(radii, np.linspace(-half_length, half_length, rings + 1), segments)]
    if cap_end:
        parts.append(lathe(np.array([0.0, 1.0]), np.full(2, -half_length), segments))
    return concatenate_geometry(parts)


def capsule_solid(
    hemisphere_rings: int, cylinder_rings: int, segments: int, half_length: float
) -> tuple[np.ndarray, np.ndarray]:
    """Cylinder (radius 1, half length ``half_length``) closed by two unit hemispheres."""
    theta = np.linspace(-0.5 * np.pi, 0.0, hemisphere_rings + 1)  # bottom hemisphere
    bottom_r, bottom_y = np.cos(theta), np.sin(theta) - half_length
    side_y = np.linspace(-half_length, half_length, cylinder_rings + 1)[1:-1]
    radii = np.concatenate([bottom_r, np.ones(len(side_y)), bottom_r[::-1]])
    heights = np.concatenate([bottom_y, side_y, -bottom_y[::-1]])
    radii[[0, -1]] = 0.0  # exact poles
    return lathe(radii, heights, segments)


def lathe(radii: np.ndarray, heights: np.ndarray, segments: int) -> tuple[np.ndarray, np.ndarray]:
    """Sweep the profile ``(radii[k], heights[k])`` around the Y axis.

    A profile point with radius 0 at either end becomes one pole vertex closed by a
    triangle fan; every other point becomes a ring of ``segments`` vertices. The profile
    must run along the outside of the solid from bottom to top for outward normals.

    Returns
    -------
    vertices : (V, 3) float64 ; faces : (F, 3) int64
    """
    phi = 2.0 * np.pi * np.arange(segments) / segments
    ring_dir = np.stack([np.sin(phi), np.zeros(segments), np.cos(phi)], axis=1)  # (S, 3)
    vertices: list[np.ndarray] = []  # one (1, 3) pole or (S, 3) ring per profile point
    ring_start: list[int] = []  # index of each ring's first vertex
    for k, (r, y) in enumerate(zip(radii, heights, strict=True)):
        ring_start.append(sum(len(v) for v in vertices))
        if r == 0.0 and k in (0, len(radii) - 1):
            vertices.append(np.array([[0.0, y, 0.0]]))  # pole
        else:
            vertices.append(r * ring_dir + np.array([0.0, y, 0.0]))  # p = r dir(phi) + y e_y
    faces = []
    j = np.arange(segments)
    j_next = (j + 1) % segments
    for k in range(len(radii) - 1):
        lo, hi = ring_start[k], ring_start[k + 1]
        lo_is_pole, hi_is_pole = len(vertices[k]) == 1, len(vertices[k + 1]) == 1
        if lo_is_pole:
            faces.append(np.stack([np.full(segments, lo), hi + j_next, hi + j], axis=1))
        elif hi_is_pole:
            faces.append(np.stack([lo + j, lo + j_next, np.full(segments, hi)], axis=1))
        else:
            faces.append(np.stack([lo + j, lo + j_next, hi + j_next], axis=1))
            faces.append(np.stack([lo + j, hi + j_next, hi + j], axis=1))
    return np.concatenate(vertices), np.concatenate(faces).astype(np.int64)


def concatenate_geometry(
    parts: list[tuple[np.ndarray, np.ndarray]],
) -> tuple[np.ndarray, np.ndarray]:
    """Join ``(vertices, faces)`` pairs into one mesh, offsetting the face indices."""
    offsets = np.cumsum([0] + [len(v) for v, _ in parts[:-1]])
    vertices = np.concatenate([v for v, _ in parts])
    faces = np.concatenate([f + off for (_, f), off in zip(parts, offsets, strict=True)])
    return vertices, faces.astype(np.int64)
