"""Habitat's object API: ``RigidObjectManager`` (``MotionType`` in :mod:`motion_type`,
``ManagedRigidObject`` in :mod:`object_properties`, on its base ``ManagedPhysicsObject`` in
:mod:`physics_object`).

A ``ManagedRigidObject`` is a thin handle on one body of the :class:`PhysicsWorld`: every
property reads or writes the world's ``body_*`` arrays, so an object is never out of sync
with the simulation. Properties return copies (``Vector3``/``Quaternion``), so
``obj.translation += [0, 0, 0.01]`` goes through the setter. Setters validate their input
(ValueError naming the value, state unchanged). After removal ``is_alive`` is False and any
other access raises :class:`DeadObjectError`.

Object ids: the stage is 0, objects count from 1. Handles: ``<template stem>_:NNNN`` with
NNNN = 1 + the largest counter in use for that stem (0000 for the first).
"""

from __future__ import annotations

import dataclasses
import re
import warnings
from pathlib import Path

import numpy as np

from engine.templates.managers import unknown_handle_message

from ..core.bodies import DYNAMIC, KINEMATIC, STATIC
from ..core.motion_type import MotionType
from .body_builder import describe_object
from .mass_ratio import warn_beyond_stable_ratio
from .object_properties import DeadObjectError, ManagedRigidObject


class RigidObjectManager:
    """Creates, finds and removes rigid objects (Habitat's ``RigidObjectManager``)."""

    def __init__(self, world, template_manager, root_node) -> None:
        self._world = world
        self._templates = template_manager
        self._root_node = root_node
        self._objects: dict[int, ManagedRigidObject] = {}

    # -- adding ----------------------------------------------------------------------------
    def add_object_by_template_id(
        self, template_id: int, attachment_node=None, light_setup_key: str = ""
    ):
        """Add an object from template ``template_id``; None (with a warning) if unknown.
        ``light_setup_key`` names the light setup it is drawn with (engine.gfx)."""
        if isinstance(template_id, bool) or not isinstance(template_id, int):
            raise TypeError(f"template_id must be an int, got {template_id!r}")
        if not self._templates.get_library_has_id(template_id):
            warnings.warn(f"no object template with id {template_id}", stacklevel=2)
            return None
        return self._add(
            self._templates.get_template_by_id(template_id), attachment_node, light_setup_key
        )

    def add_object_by_template_handle(
        self, object_lib_handle: str, attachment_node=None, light_setup_key: str = ""
    ):
        """Add an object from the template with this exact handle; None if unknown."""
        if not isinstance(object_lib_handle, str):
            raise TypeError(f"template handle must be a str, got {object_lib_handle!r}")
        if not self._templates.get_library_has_handle(object_lib_handle):
            message = unknown_handle_message(self._templates, object_lib_handle)
            warnings.warn(message, stacklevel=2)
            return None
        return self._add(
            self._templates.get_template_by_handle(object_lib_handle),
            attachment_node,
            light_setup_key,
        )

    def add_object_instance(self, template, light_setup_key: str = "") -> ManagedRigidObject:
        """Add an object from a template that need not be registered (a scene instance's
        scaled copy, as Habitat's ``PhysicsManager::addObjectInstance``)."""
        return self._add(template, None, light_setup_key)

    def save_reset_pose(self, obj: ManagedRigidObject) -> None:
        """Make the object's current pose the one ``sim.reset()`` returns it to (a scene
        instance's pose, as Habitat's ``resetStateFromSceneInstanceAttr``)."""
        index = obj._check()
        bodies = self._world.bodies
        self._world.creation_state[index] = (
            bodies.body_position[index].copy(),
            bodies.body_rotation[index].copy(),
        )

    def _add(self, template, attachment_node, light_setup_key: str = "") -> ManagedRigidObject:
        from engine.scene.graph import Drawable, SceneNode
        from engine.scene.visual_nodes import build_visual_nodes

        if not isinstance(light_setup_key, str):
            raise TypeError(f"light_setup_key must be a str, got {light_setup_key!r}")
        description = describe_object(template)  # raises before the world changes
        world = self._world
        index = world.add_body(description, template)
        world.mass_ratio_warned.discard(index)  # a reused slot is checked afresh
        warn_beyond_stable_ratio(world.bodies, index, world.mass_ratio_warned)
        root = attachment_node if attachment_node is not None else SceneNode(self._root_node)
        visual = SceneNode(root, name="visual")
        visual.translation = -description.com
        drawables = [
            Drawable(mesh, True, int(template.semantic_id), light_setup_key)
            for mesh in description.render_meshes
        ]
        visual_nodes = build_visual_nodes(visual, drawables, str(template.render_asset_handle))
        world.nodes[index] = root
        world.render_meshes[index] = [
            dataclasses.replace(m, vertices=np.asarray(m.vertices) - description.com)
            for m in description.render_meshes
        ]
        from .velocity_control import VelocityControl

        world.velocity_controls[index] = VelocityControl()
        obj = ManagedRigidObject(
            world, index, self._new_handle(template.handle), template, description, root, visual
        )
        obj._visual_nodes = visual_nodes
        if attachment_node is not None:
            matrix = attachment_node.world_matrix()
            world.node_sync.forget(index)
            from ..core.quaternions import matrix_to_quat

            rotation = matrix[:3, :3] / np.linalg.norm(matrix[:3, :3], axis=0)
            world.set_body_pose(index, matrix[:3, 3].copy(), matrix_to_quat(rotation))
            world.creation_state[index] = (matrix[:3, 3].copy(), matrix_to_quat(rotation))
        world.node_sync.write_node(index)
        self._objects[index] = obj
        return obj

    def _new_handle(self, template_handle: str) -> str:
        name = Path(template_handle).name
        stem = re.sub(r"\.object_config\.json$", "", name)
        pattern = re.compile(re.escape(stem) + r"_:(\d{4,})$")
        used = [int(m.group(1)) for h in self.get_object_handles() if (m := pattern.match(h))]
        return f"{stem}_:{(max(used) + 1) if used else 0:04d}"

    # -- removing ----------------------------------------------------------------------------
    def remove_object_by_id(
        self, object_id: int, delete_object_node: bool = True, delete_visual_node: bool = True
    ) -> None:
        """Remove object ``object_id``: KeyError if there is none."""
        obj = self.get_object_by_id(object_id)
        if obj is None:
            raise KeyError(f"no rigid object with id {object_id!r}")
        if delete_visual_node:
            obj._visual_node.drawables = []
            obj._visual_node.parent = None
        if delete_object_node:
            obj._root_node.parent = None
        self._world.remove_body(obj._index)
        obj._alive = False
        del self._objects[obj._index]

    def remove_object_by_handle(
        self, handle: str, delete_object_node: bool = True, delete_visual_node: bool = True
    ) -> None:
        """Remove the object with this handle: KeyError if there is none."""
        obj = self.get_object_by_handle(handle)
        if obj is None:
            raise KeyError(f"no rigid object with handle {handle!r}")
        self.remove_object_by_id(obj.object_id, delete_object_node, delete_visual_node)

    def remove_all_objects(
        self, delete_object_node: bool = True, delete_visual_node: bool = True
    ) -> None:
        for object_id in sorted(self._objects):
            self.remove_object_by_id(object_id, delete_object_node, delete_visual_node)

    # -- finding -------------------------------------------------------------------------------
    def get_num_objects(self) -> int:
        return len(self._objects)

    def get_object_handles(self, search_str: str = "", contains: bool = True) -> list[str]:
        """Handles (sorted) that contain (or, with ``contains=False``, do not contain)
        ``search_str``, case-insensitive."""
        key = search_str.lower()
        handles = [o._handle for o in self._objects.values()]
        return sorted(h for h in handles if (key in h.lower()) == contains)

    def get_object_by_id(self, object_id: int):
        """The object, or None if no live object has this id."""
        if isinstance(object_id, bool) or not isinstance(object_id, int):
            raise TypeError(f"object_id must be an int, got {object_id!r}")
        return self._objects.get(object_id)

    def get_object_by_handle(self, handle: str):
        """The object with this exact handle, or None."""
        for obj in self._objects.values():
            if obj._handle == handle:
                return obj
        return None

    def get_objects_by_handle_substring(self, search_str: str = "", contains: bool = True):
        """``{handle: object}`` for the handles matching like :meth:`get_object_handles`."""
        return {
            h: self.get_object_by_handle(h) for h in self.get_object_handles(search_str, contains)
        }

    def get_object_handle_by_id(self, object_id: int) -> str:
        obj = self.get_object_by_id(object_id)
        if obj is None:
            raise KeyError(f"no rigid object with id {object_id!r}")
        return obj._handle

    def get_object_id_by_handle(self, handle: str) -> int:
        obj = self.get_object_by_handle(handle)
        if obj is None:
            raise KeyError(f"no rigid object with handle {handle!r}")
        return obj._index

    def get_library_has_handle(self, handle: str) -> bool:
        return self.get_object_by_handle(handle) is not None

    def get_library_has_id(self, object_id: int) -> bool:
        return self.get_object_by_id(object_id) is not None


__all__ = [
    "DYNAMIC",
    "KINEMATIC",
    "STATIC",
    "DeadObjectError",
    "ManagedRigidObject",
    "MotionType",
    "RigidObjectManager",
]
