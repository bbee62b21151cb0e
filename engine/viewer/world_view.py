"""What the viewer reads from a :class:`~engine.simulator.Simulator`: parts, poses, frusta.

The viewer reads a simulator only the way a user can: it walks the scene graph from
``sim.get_active_scene_graph().get_root_node()`` (every node's ``drawables`` are the meshes
the sensors draw), asks the rigid object manager which node belongs to which object
(``obj.visual_scene_nodes``), and reads node poses with ``transformation_matrix()`` and the
agents' sensors with their specifications. Nothing private is touched, so what the viewer
shows is what a student could compute in a notebook cell.

Two kinds of data come out:

- :class:`Part` (once): one drawable mesh in its node's frame, ``vertices (V, 3) float32``,
  ``faces (F, 3) uint32``, ``colors (V,) uint32`` packed ``0xRRGGBB`` (texture sampled at the
  vertices, times the material's base colour), and the object id it belongs to (0 for the
  stage, -1 for a node of no object);
- poses (every frame): ``(4, 4) float32`` world-from-node matrices keyed by part key.

Conventions: world frame Y up, -Z forward, meters. Cameras look down their local -Z axis.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from engine.viewer.settings import FRUSTUM_DEPTH, STAGE_OBJECT_ID

__all__ = [
    "Part",
    "agent_segments",
    "collect_parts",
    "frustum_segments",
    "node_pose",
    "object_nodes",
    "pack_rgb",
    "part_poses",
]


@dataclass
class Part:
    """One drawable mesh of the scene graph, in its node's frame.

    Attributes
    ----------
    key : str
        Unique name, ``"<node name>#<node serial>/<drawable index>"``.
    node : SceneNode
        The node whose world matrix places the mesh.
    vertices : (V, 3) float32
        Positions in the node's frame, meters.
    faces : (F, 3) uint32
        Triangle vertex indices, counter-clockwise seen from outside.
    colors : (V,) uint32
        Packed ``0xRRGGBB`` per vertex.
    object_id : int
        Object id of the node (0 the stage, -1 for a node no object owns).
    """

    key: str
    node: Any
    vertices: np.ndarray
    faces: np.ndarray
    colors: np.ndarray
    object_id: int


def pack_rgb(rgb: np.ndarray) -> np.ndarray:
    """Pack ``(..., 3)`` uint8-range colours into ``(...)`` uint32 ``0xRRGGBB`` (k3d's colours)."""
    rgb = np.clip(np.rint(rgb), 0, 255).astype(np.uint32)
    # packed = R * 2^16 + G * 2^8 + B
    return (rgb[..., 0] << 16) | (rgb[..., 1] << 8) | rgb[..., 2]


def vertex_colors(mesh: Any) -> np.ndarray:
    """``(V,)`` packed colours of a :class:`~engine.scene.assets.MeshData`, as the renderer shades.

    Vertex colours when the mesh has them, else the texture sampled (nearest texel) at each
    vertex's UV, else the flat base colour; every one multiplied by ``base_color / 255``.
    """
    n_vertices = len(mesh.vertices)
    base = np.asarray(mesh.base_color, dtype=np.float64)[:3] / 255.0
    if mesh.vertex_colors is not None:
        rgb = np.asarray(mesh.vertex_colors, dtype=np.float64)[:, :3]
    elif mesh.texture is not None and mesh.uvs is not None:
        texture = np.asarray(mesh.texture)
        h, w = texture.shape[:2]
        uv = np.clip(np.asarray(mesh.uvs, dtype=np.float64), 0.0, 1.0)
        # OpenGL convention of MeshData: texel column u * (w - 1), row (1 - v) * (h - 1)
        cols = np.rint(uv[:, 0] * (w - 1)).astype(np.int64)
        rows = np.rint((1.0 - uv[:, 1]) * (h - 1)).astype(np.int64)
        rgb = texture[rows, cols, :3].astype(np.float64)
    else:
        rgb = np.full((n_vertices, 3), 255.0)
    return pack_rgb(rgb * base)


def object_nodes(sim: Any) -> dict[int, int]:
    """Map ``id(node)`` of every object's visual and root nodes to its object id.

    Read from the rigid object manager (``get_objects_by_handle_substring`` and each
    object's ``visual_scene_nodes``), as a user would.
    """
    owners: dict[int, int] = {}
    objects = sim.get_rigid_object_manager().get_objects_by_handle_substring("")
    for obj in objects.values():
        for node in obj.visual_scene_nodes:
            owners[id(node)] = obj.object_id
        owners[id(obj.root_scene_node)] = obj.object_id
    return owners


def collect_parts(sim: Any) -> list[Part]:
    """Every drawable mesh of the simulator's scene graph as a :class:`Part`.

    Walks the nodes from the root in the scene graph's order; the stage node's meshes get
    object id 0, an object's visual node its object id.
    """
    root = sim.get_active_scene_graph().get_root_node()
    owners = object_nodes(sim)
    parts: list[Part] = []
    for serial, node in enumerate(root.descendants()):
        for index, drawable in enumerate(getattr(node, "drawables", [])):
            mesh = drawable.mesh
            object_id = owners.get(id(node), STAGE_OBJECT_ID if node.name == "stage" else -1)
            parts.append(
                Part(
                    key=f"{node.name}#{serial}/{index}",
                    node=node,
                    vertices=np.asarray(mesh.vertices, dtype=np.float32),
                    faces=np.asarray(mesh.faces, dtype=np.uint32),
                    colors=vertex_colors(mesh),
                    object_id=object_id,
                )
            )
    return parts


def node_pose(node: Any) -> np.ndarray:
    """``(4, 4) float32`` world-from-node matrix (Habitat's ``transformation_matrix()``)."""
    return np.asarray(node.transformation_matrix(), dtype=np.float32)


def part_poses(parts: list[Part]) -> dict[str, np.ndarray]:
    """World-from-node matrices of every part, keyed by part key."""
    return {part.key: node_pose(part.node) for part in parts}


def frustum_segments(
    world_from_camera: np.ndarray, hfov_deg: float, resolution: Any, depth: float = FRUSTUM_DEPTH
) -> np.ndarray:
    """``(8, 2, 3)`` world-frame segments of a pinhole camera's view frustum cut at ``depth``.

    Four rays from the optical centre to the corners of the image rectangle at z = -depth,
    then the rectangle's four edges. ``hfov_deg`` is horizontal (Habitat's ``hfov``) and
    ``resolution`` is ``[height, width]``, so the half height is ``half_width * H / W``.
    """
    height, width = float(resolution[0]), float(resolution[1])
    half_w = depth * np.tan(np.radians(hfov_deg) / 2.0)
    half_h = half_w * height / width
    corners_cam = np.array(
        [[-half_w, -half_h, -depth], [half_w, -half_h, -depth], [half_w, half_h, -depth],
         [-half_w, half_h, -depth]]
    )  # fmt: skip
    rotation, origin = world_from_camera[:3, :3], world_from_camera[:3, 3]
    corners = corners_cam @ rotation.T + origin  # x_world = R x_cam + t, row by row
    rays = np.stack([np.broadcast_to(origin, (4, 3)), corners], axis=1)
    edges = np.stack([corners, np.roll(corners, -1, axis=0)], axis=1)
    return np.concatenate([rays, edges]).astype(np.float32)


def agent_segments(sim: Any, n_sides: int = 12) -> np.ndarray:
    """``(k, 2, 3)`` segments drawing every agent and its sensors' frusta.

    An agent is its configuration's cylinder (``height``, ``radius``, standing on the agent
    node's origin) as a circle at the feet, one at the head and four vertical lines; each
    camera sensor adds :func:`frustum_segments` of its ``sensor.object`` node.
    """
    segments: list[np.ndarray] = []
    angles = np.linspace(0.0, 2.0 * np.pi, n_sides + 1)
    ring = np.stack([np.cos(angles), np.zeros_like(angles), np.sin(angles)], axis=1)
    for agent in sim.agents:
        cfg = agent.agent_config
        base = node_pose(agent.scene_node)[:3, 3].astype(np.float64)
        up = np.array([0.0, float(cfg.height), 0.0])
        circle = base + float(cfg.radius) * ring
        for lift in (np.zeros(3), up):
            segments.append(np.stack([circle[:-1] + lift, circle[1:] + lift], axis=1))
        posts = circle[: n_sides : max(1, n_sides // 4)]
        segments.append(np.stack([posts, posts + up], axis=1))
        for sensor in agent.sensors.values():
            spec = sensor.specification()
            pose = node_pose(sensor.object).astype(np.float64)
            segments.append(frustum_segments(pose, float(spec.hfov), spec.resolution))
    if not segments:
        return np.zeros((0, 2, 3), dtype=np.float32)
    return np.concatenate(segments).astype(np.float32)
