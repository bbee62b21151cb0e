"""From an object template to a body: render meshes, collision shapes, mass properties.

Habitat's rules (docs/habitat_api.md, "Objects"):

* render meshes: the render asset (a Magnum primitive scaled by the template ``scale``, or a
  file loaded with the template's up/front/scale/units_to_meters);
* collision: the collision asset (the render asset when empty). A primitive collision asset
  is an exact primitive (scaled by ``scale x collision_asset_size``); mesh assets become one
  convex hull per mesh, or one joined hull with ``join_collision_meshes`` (beyond
  ``MAX_HULL_POINTS`` points the hull of a capped sample, cached per point set:
  ``hull_sampling.py``); with
  ``use_bounding_box_for_collision`` a box of the collision meshes' AABB;
* the body frame's origin is the center of mass: the center of the render meshes' AABB unless
  the template gives ``COM``; shapes and meshes are shifted by ``-COM``;
* mass from the template (1 kg default); inertia from the template when non-zero, else the
  collision shape's uniform-density inertia scaled to that mass.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
from scipy.spatial import QhullError

from ..core.settings import MAX_COORDINATE, MIN_BOX_HALF_EXTENT
from ..core.shapes import Shape, box_shape, convex_shape, primitive_shape, unit_mass_inertia
from .hull_sampling import cached_hull_points


@dataclass
class BodyDescription:
    """Everything a new body needs, in its body (COM) frame.

    Attributes
    ----------
    shapes : list of Shape. render_meshes : list of MeshData in the asset frame (the visual
        node is offset by -COM).
    com : (3,) COM in the asset frame, m. mass : kg. inertia : (3,) kg m^2.
    aabb_min, aabb_max : (3,) render AABB in the body frame, m.
    """

    shapes: list
    render_meshes: list
    com: np.ndarray
    mass: float
    inertia: np.ndarray
    aabb_min: np.ndarray
    aabb_max: np.ndarray


def _load(handle: str, template) -> list:
    """Meshes of an asset handle in the object's frame, scaled."""
    from engine.scene.assets import load_meshes, primitive_meshes

    scale = np.asarray(template.scale, dtype=np.float64)
    if _is_primitive(handle):
        return [
            dataclasses.replace(m, vertices=np.asarray(m.vertices) * scale)
            for m in primitive_meshes(handle)
        ]
    return load_meshes(
        handle,
        up=np.asarray(template.orient_up).tolist(),
        front=np.asarray(template.orient_front).tolist(),
        scale=scale.tolist(),
        units_to_meters=template.units_to_meters,
    )


def _is_primitive(handle: str) -> bool:
    from engine.templates.attributes import is_primitive_handle

    return is_primitive_handle(handle)


def describe_object(template) -> BodyDescription:
    """Build the :class:`BodyDescription` of an ``ObjectAttributes`` template."""
    render_handle = template.render_asset_handle
    collision_handle = template.collision_asset_handle or render_handle
    if not render_handle and not collision_handle:
        raise ValueError(f"template {template.handle!r} has no render or collision asset")
    render = _load(render_handle or collision_handle, template)
    points = np.concatenate([np.asarray(m.vertices, dtype=np.float64) for m in render])
    if template.compute_COM_from_shape:
        com = 0.5 * (points.min(0) + points.max(0))  # AABB center of the render meshes
    else:
        com = np.asarray(template.com, dtype=np.float64)
    shapes = _shapes_around_com(template, collision_handle, render_handle, com)
    _check_size(template, shapes)
    mass = float(template.mass)
    inertia = np.asarray(template.inertia, dtype=np.float64)
    if not np.any(inertia):
        inertia = mass * _unit_inertia(shapes)
    if np.any(inertia <= 0) or not np.all(np.isfinite(inertia)):
        raise ValueError(f"template {template.handle!r}: inertia must be positive, got {inertia}")
    return BodyDescription(
        shapes, render, com, mass, inertia, points.min(0) - com, points.max(0) - com
    )


def _shapes_around_com(template, collision_handle, render_handle, com) -> list[Shape]:
    """The collision shapes shifted by ``-COM``; a ValueError naming the COM when it is
    beyond float32 coordinates (as poses are) or so far out that the shifted hull is
    lost to rounding (qhull then finds no simplex)."""
    if not np.all(np.abs(com) <= MAX_COORDINATE):
        raise ValueError(
            f"template {template.handle!r}: COM {com.tolist()} is beyond float32 coordinates "
            f"(|x| <= {MAX_COORDINATE:.7g} m)"
        )
    try:
        return _collision_shapes(template, collision_handle, render_handle, com)
    except QhullError as error:
        raise ValueError(
            f"template {template.handle!r}: no collision hull around COM {com.tolist()} "
            f"(scale {list(template.scale)}): the shifted shape is lost to rounding"
        ) from error


def _check_size(template, shapes: list[Shape]) -> None:
    """Refuse collision shapes thinner than ``MIN_BODY_DIMENSION`` (or with a degenerate
    hull): contact geometry below that size is lost to rounding and fcl's tolerances."""
    from ..core.settings import MIN_BODY_DIMENSION

    for shape in shapes:
        thickness = 2.0 * shape.min_half_extent
        degenerate = shape.plane_normals is not None and len(shape.plane_normals) < 4
        if not thickness >= MIN_BODY_DIMENSION or degenerate:
            raise ValueError(
                f"template {template.handle!r}: collision shape is {thickness:.3g} m thick in "
                f"its smallest dimension; the minimum is {MIN_BODY_DIMENSION} m "
                f"(engine.physics.core.settings.MIN_BODY_DIMENSION); scale {list(template.scale)}"
            )


def _collision_shapes(template, collision_handle, render_handle, com) -> list[Shape]:
    name = f"collision asset of {template.handle!r}"
    scale = np.asarray(template.scale, dtype=np.float64)
    if _is_primitive(collision_handle) and not template.bounding_box_collisions:
        size = np.asarray(template.collision_asset_size, dtype=np.float64)
        if collision_handle == render_handle or not template.collision_asset_handle:
            size = np.ones(3)
        return [primitive_shape(collision_handle, scale * size, -com)]
    meshes = _load(collision_handle, template)
    clouds = [np.asarray(m.vertices, dtype=np.float64) - com for m in meshes if len(m.vertices)]
    if not clouds:
        raise ValueError(f"{name} has no vertices")
    if template.bounding_box_collisions:
        cloud = np.concatenate(clouds)
        lo, hi = cloud.min(0), cloud.max(0)
        return [box_shape(np.maximum(0.5 * (hi - lo), MIN_BOX_HALF_EXTENT), 0.5 * (lo + hi))]
    if template.join_collision_meshes or len(clouds) == 1:
        return [convex_shape(cached_hull_points(np.concatenate(clouds)), name)]
    return [
        convex_shape(cached_hull_points(cloud), f"{name} mesh {i}")
        for i, cloud in enumerate(clouds)
    ]


def _unit_inertia(shapes: list[Shape]) -> np.ndarray:
    """Diagonal inertia per kg about the body origin of the union of the shapes."""
    if len(shapes) == 1:
        center, inertia = unit_mass_inertia(shapes[0])
    else:
        joined = convex_shape(np.concatenate([s.hull_vertices for s in shapes]), "joined hull")
        center, inertia = unit_mass_inertia(joined)
    # parallel axis theorem to the body origin: I_xx += (y^2 + z^2) per kg
    c2 = center**2
    return inertia + np.array([c2[1] + c2[2], c2[0] + c2[2], c2[0] + c2[1]])
