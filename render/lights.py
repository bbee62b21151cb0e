"""Light setups and the Lambert factor: how bright a lit surface is.

A lit pixel's color is multiplied by a light factor (``render.shade``)::

    light = clamp(ambient + sum_k c_k max(0, n . l_k), 0, 1)

with ``n`` the unit surface normal (world frame) and, per light ``k``, its intensity ``c_k``
and the unit direction ``l_k`` towards it. Habitat's ``LightInfo`` lists become
:class:`Lights`: each light has a homogeneous vector ``(x, y, z, w)``: ``w = 0`` is a
directional light shining *from* direction ``(x, y, z)`` (``l_k`` = that direction,
normalized), ``w = 1`` a point light at ``(x, y, z)`` (``l_k = normalize(p_k - p)`` from the
surface point ``p``: the face centroid, or the vertex), and a frame its vector is given in
(world, camera or mesh, resolved with the camera and mesh poses of the frame). An empty
setup is flat shading (``light = 1``, Habitat's ``NO_LIGHT_KEY``).

rigidsim's default setup (:data:`DEFAULT_LIGHTS`, Habitat's default object lights): 4
directional lights travelling along ``d = (+-1, -0.5, 0)`` and ``(0, -0.5, +-1)`` (world
frame, normalized), each of intensity ``DIFFUSE = 0.5``, plus ``AMBIENT = 0.4``: the top face
(``n . l_k = 0.447`` for all 4 lights) gets 1.0, a vertical side facing +-x or +-z 0.85,
the bottom 0.4 (:func:`face_light_factors`). These are constants; another setup is another
:class:`Lights` value.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: rigidsim's default light setup (constants: a different setup is a :class:`Lights`)
AMBIENT = 0.4
DIFFUSE = 0.5
#: world-frame directions the 4 default lights travel along (unit vectors)
LIGHT_DIRECTIONS = np.array(
    [[1.0, -0.5, 0.0], [-1.0, -0.5, 0.0], [0.0, -0.5, 1.0], [0.0, -0.5, -1.0]]
) / np.sqrt(1.25)
#: frames a light vector may be given in (Habitat's LightPositionModel Global, Camera, Object)
LIGHT_FRAMES = ("world", "camera", "mesh")


@dataclass(frozen=True)
class Lights:
    """A light setup as plain arrays (see the module docstring).

    Attributes
    ----------
    vectors : (L, 4) float, ``(x, y, z, w)``: ``w = 0`` direction towards the light,
        ``w = 1`` light position.
    intensities : (L,) float, ``c_k`` (gray; Habitat's color, averaged over RGB upstream).
    frames : L entries of ``LIGHT_FRAMES``.
    ambient : float, added to every lit pixel (ignored when ``L == 0``: flat shading).
    """

    vectors: np.ndarray
    intensities: np.ndarray
    frames: tuple
    ambient: float = AMBIENT

    def __post_init__(self) -> None:
        vectors = np.asarray(self.vectors, dtype=np.float64).reshape(-1, 4)
        intensities = np.asarray(self.intensities, dtype=np.float64).reshape(-1)
        if len(intensities) != len(vectors) or len(self.frames) != len(vectors):
            raise ValueError("Lights needs one intensity and one frame per light vector")
        if not (np.all(np.isfinite(vectors)) and np.all(np.isfinite(intensities))):
            raise ValueError("light vectors and intensities must be finite")
        if not np.all((vectors[:, 3] == 0.0) | (vectors[:, 3] == 1.0)):
            raise ValueError("light vectors need w == 0 (directional) or w == 1 (point)")
        if any(frame not in LIGHT_FRAMES for frame in self.frames):
            raise ValueError(f"light frames must be in {LIGHT_FRAMES}, got {self.frames}")
        object.__setattr__(self, "vectors", vectors)
        object.__setattr__(self, "intensities", intensities)
        object.__setattr__(self, "frames", tuple(self.frames))

    @property
    def is_flat(self) -> bool:
        return len(self.vectors) == 0

    def in_world(
        self, world_from_camera: np.ndarray | None, world_from_mesh: np.ndarray | None
    ) -> np.ndarray:
        """The ``(L, 4)`` vectors in the world frame (camera / mesh frames resolved)."""
        out = self.vectors.copy()
        for k, frame in enumerate(self.frames):
            if frame == "camera" and world_from_camera is not None:
                out[k] = world_from_camera @ self.vectors[k]
            elif frame == "mesh" and world_from_mesh is not None:
                out[k] = world_from_mesh @ self.vectors[k]
        return out

    @property
    def has_mesh_frame(self) -> bool:
        return "mesh" in self.frames


def lambert_factors(
    normals_world: np.ndarray,
    points_world: np.ndarray | None,
    lights: Lights,
    world_vectors: np.ndarray,
) -> np.ndarray:
    """``clamp(ambient + sum_k c_k max(0, n . l_k), 0, 1)`` per row, ``(T,)`` float32.

    ``normals_world`` (T, 3) any length (zero: ambient only); ``points_world`` (T, 3) surface
    points for point lights; ``world_vectors`` (L, 4) the lights in the world frame.
    """
    if lights.is_flat:
        return np.ones(len(normals_world), dtype=np.float32)
    length = np.linalg.norm(normals_world, axis=1, keepdims=True)
    unit = np.divide(normals_world, length, out=np.zeros_like(normals_world), where=length > 0)
    total = np.zeros(len(unit))
    for vector, intensity in zip(world_vectors, lights.intensities, strict=True):
        if vector[3] == 0.0:  # directional: l = normalize(x, y, z)
            to_light = vector[:3] / max(np.linalg.norm(vector[:3]), 1e-300)
            n_dot_l = unit @ to_light
        else:  # point: l = normalize(p_light - p)
            offset = vector[:3] - points_world
            distance = np.linalg.norm(offset, axis=1)
            n_dot_l = np.einsum("ij,ij->i", unit, offset) / np.maximum(distance, 1e-300)
        total += intensity * np.maximum(n_dot_l, 0.0)
    return np.clip(lights.ambient + total, 0.0, 1.0).astype(np.float32)


#: rigidsim's default setup as :class:`Lights`: the 4 directional lights (shining from
#: ``-d_k``) of intensity ``DIFFUSE`` and ambient ``AMBIENT`` (``face_light_factors``).
DEFAULT_LIGHTS = Lights(
    np.hstack([-LIGHT_DIRECTIONS, np.zeros((4, 1))]), np.full(4, DIFFUSE), ("world",) * 4, AMBIENT
)


def face_light_factors(normals_world: np.ndarray) -> np.ndarray:
    """Lambert factor of Habitat's default light setup per face, ``(T,)`` float32.

    Parameters
    ----------
    normals_world : (T, 3) float, face normals in the world frame (any length; zero-length
        normals, from degenerate faces, get the ambient term only).
    """
    length = np.linalg.norm(normals_world, axis=1, keepdims=True)
    unit = np.divide(normals_world, length, out=np.zeros_like(normals_world), where=length > 0)
    n_dot_l = unit @ (-LIGHT_DIRECTIONS.T)  # (T, 4): n . l_k with l_k = -d_k (towards the light)
    light = AMBIENT + DIFFUSE * np.maximum(n_dot_l, 0.0).sum(axis=1)
    return np.clip(light, 0.0, 1.0).astype(np.float32)  # clamp(ambient + k sum max(0, n.l), 0, 1)
