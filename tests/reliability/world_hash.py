"""One fingerprint of everything a bad input must leave untouched.

``world_hash(sim)`` is a SHA-256 over: every body's state (the physics world's own
``state_hash``: poses, velocities, forces, masses, manifolds, time, gravity), the live objects
(ids, handles, velocity controls, scene-node transforms), every template library (handles,
ids, locks, every field and the user configuration), the navmesh (all arrays and settings)
and the agents' poses. The reliability tests compare it before and after each refused call.
"""

from __future__ import annotations

import hashlib
from typing import Any

import numpy as np


def _feed(digest, value: Any) -> None:
    """Add ``value`` (nested containers, arrays, numbers, strings) to ``digest``."""
    if isinstance(value, np.ndarray):
        digest.update(str((value.dtype, value.shape)).encode())
        digest.update(np.ascontiguousarray(value).tobytes())
    elif isinstance(value, dict):
        for key in sorted(value, key=repr):
            _feed(digest, repr(key))
            _feed(digest, value[key])
    elif isinstance(value, list | tuple | set | frozenset):
        items = sorted(value, key=repr) if isinstance(value, set | frozenset) else value
        digest.update(f"[{len(items)}".encode())
        for item in items:
            _feed(digest, item)
    elif hasattr(value, "__array__") and not isinstance(value, str | bytes):
        _feed(digest, np.asarray(value))
    else:
        digest.update(repr(value).encode())


def _templates(manager) -> dict:
    """Every template of a manager: id, lock, fields and user configuration."""
    library = {}
    for handle, template in manager._templates.items():
        library[handle] = (
            template.template_id,
            handle in manager._locked,
            template.as_dict(),
            template.get_user_config().to_dict(),
        )
    return library


def _objects(world) -> list:
    """Live objects: id, handle, velocity control and root-node transform."""
    manager = world.rigid_object_manager
    rows = []
    for index, obj in sorted(manager._objects.items()):
        node = obj._root_node
        rows.append(
            (
                index,
                obj._handle,
                obj._alive,
                repr(world.velocity_controls[index]),
                node._translation,
                node._rotation,
                node._scaling,
            )
        )
    return rows


def _navmesh(pathfinder) -> Any:
    if not pathfinder.is_loaded:
        return "no navmesh"
    data = pathfinder.navmesh_data
    return (
        data.settings.to_dict(),
        data.bounds,
        data.origin_xz,
        data.cell_size,
        data.floor,
        data.ceiling,
        data.navigable,
        data.links,
        data.island,
    )


def world_hash(sim) -> str:
    """SHA-256 of the whole simulator state (see the module docstring)."""
    digest = hashlib.sha256()
    world = sim.get_physics_world()
    _feed(digest, world.state_hash())
    _feed(digest, world.rigid_object_manager.get_num_objects())
    _feed(digest, _objects(world))
    for manager in (
        sim.get_object_template_manager(),
        sim.get_asset_template_manager(),
        sim.get_stage_template_manager(),
        sim.get_physics_template_manager(),
    ):
        _feed(digest, _templates(manager))
    _feed(digest, _navmesh(sim.pathfinder))
    for agent in sim.agents:
        _feed(digest, agent.scene_node.world_matrix())
    return digest.hexdigest()


def bodies_are_finite(world) -> bool:
    """True when every live body's pose and velocities are finite."""
    b, n = world.bodies, world.bodies.count
    alive = b.body_alive[:n]
    return all(
        bool(np.all(np.isfinite(getattr(b, name)[:n][alive])))
        for name in (
            "body_position",
            "body_rotation",
            "body_linear_velocity",
            "body_angular_velocity",
            "body_force",
            "body_torque",
        )
    )
