"""The scenes ``bench_render.py`` times: what is drawn and from where.

Each builder returns plain :class:`render.RenderMesh` lists (and camera poses), so the
benchmark can hand the same triangles to rigidsim's rasterizer and to pybullet's
TinyRenderer:

* :func:`sphere_scene`: a unit sphere of about N triangles with vertex colors, lit;
* :func:`plane_and_boxes_scene`: a textured floor filling the view and 5 lit boxes;
* :func:`apartment_scenes`: the demo apartment as the tutorial's 1st- and 3rd-person
  cameras see it (the engine's own render meshes and camera poses);
* :func:`moving_boxes`: 5 boxes tumbling on the apartment's coffee table, one mesh list a
  frame (the static-layer table);
* :func:`look_at`: a camera pose (``world_from_camera``, -Z forward) from eye and target.
"""

from __future__ import annotations

import math

import numpy as np
import trimesh

from render import RenderMesh


def look_at(eye, target, up=(0.0, 1.0, 0.0)) -> np.ndarray:
    """``world_from_camera`` of a camera at ``eye`` looking at ``target`` (-Z forward)."""
    eye, target, up = (np.asarray(v, dtype=float) for v in (eye, target, up))
    back = eye - target
    back /= np.linalg.norm(back)
    right = np.cross(up, back)
    right /= np.linalg.norm(right)
    pose = np.eye(4)
    pose[:3, :3] = np.column_stack([right, np.cross(back, right), back])
    pose[:3, 3] = eye
    return pose


def sphere_scene(n_triangles: int) -> list[RenderMesh]:
    """A unit sphere of about ``n_triangles`` triangles with vertex colors, lit."""
    count = max(4, int(round(math.sqrt(n_triangles / 4))))  # uv_sphere: ~4 count^2 faces
    mesh = trimesh.creation.uv_sphere(radius=1.0, count=[count, count])
    colors = ((mesh.vertices * 0.5 + 0.5) * 255).astype(np.uint8)
    return [RenderMesh(mesh.vertices, mesh.faces, vertex_colors=colors, lit=True, semantic_id=1)]


def plane_and_boxes_scene() -> list[RenderMesh]:
    """A textured floor filling the view and 5 lit boxes close to the camera."""
    checker = (np.indices((64, 64)).sum(axis=0) // 8 % 2 * 155 + 100).astype(np.uint8)
    texture = np.repeat(checker[:, :, None], 3, axis=2)
    floor = RenderMesh(
        np.array([[-20, 0, 20], [20, 0, 20], [20, 0, -20], [-20, 0, -20]], dtype=float),
        np.array([[0, 1, 2], [0, 2, 3]]),
        uvs=np.array([[0, 0], [10, 0], [10, 10], [0, 10]], dtype=float),
        texture=texture,
        semantic_id=1,
    )
    meshes = [floor]
    box = trimesh.creation.box(extents=(0.4, 0.4, 0.4))
    for i, x in enumerate(np.linspace(-0.8, 0.8, 5)):
        pose = np.eye(4)
        pose[:3, 3] = [x, 0.2, -1.0 - 0.3 * (i % 2)]
        color = np.array([60 + 40 * i, 200 - 30 * i, 120, 255], np.uint8)
        meshes.append(
            RenderMesh(box.vertices, box.faces, pose, base_color=color, lit=True, semantic_id=2 + i)
        )
    return meshes


def apartment_scenes() -> list[tuple[str, list[RenderMesh], np.ndarray, bool]]:
    """The demo apartment seen by the tutorial's 1st- and 3rd-person cameras (engine side).

    Builds the tutorial's simulator (agent pose and sensors of ``place_agent`` and
    ``make_configuration``), then takes the exact render meshes and camera poses the engine
    renders, with back faces culled as the engine's sensors do.
    """
    from engine.demo import demo_data_path
    from engine.sensors.scene_render import _render_mesh
    from engine.tutorial.scene_setup import make_configuration, place_agent

    sim = __import__("engine").Simulator(make_configuration(str(demo_data_path())))
    place_agent(sim)
    meshes = []
    for node in sim.root_node.descendants():
        for drawable in node.drawables:
            mesh = _render_mesh(drawable)
            mesh.world_from_mesh = node.world_matrix()
            meshes.append(mesh)
    poses = {s.uuid: s.world_from_camera() for s in sim.agents[0].sensors.values()}
    sim.close()
    return [
        ("apartment, 1st person", meshes, poses["rgba_camera_1stperson"], True),
        ("apartment, 3rd person", meshes, poses["rgba_camera_3rdperson"], True),
    ]


def moving_boxes(n_frames: int) -> list[list[RenderMesh]]:
    """5 lit boxes tumbling on the apartment's coffee table, one mesh list per frame."""
    box = trimesh.creation.box(extents=(0.16, 0.24, 0.06))
    frames = []
    for frame in range(n_frames):
        meshes = []
        for i in range(5):
            angle = 0.07 * frame + i
            pose = np.eye(4)
            pose[:3, :3] = trimesh.transformations.rotation_matrix(angle, (1, 1, 0))[:3, :3]
            pose[:3, 3] = [2.39, -0.9 + 0.1 * i + 0.004 * frame, 0.22 * (i - 2)]
            color = np.array([200, 60 + 30 * i, 40, 255], np.uint8)
            meshes.append(
                RenderMesh(
                    box.vertices, box.faces, pose, base_color=color, lit=True, semantic_id=10 + i
                )
            )
        frames.append(meshes)
    return frames
