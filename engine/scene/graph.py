"""The scene graph: nodes with a local translation-rotation-scaling (TRS) transform.

A :class:`SceneNode` holds its pose relative to its parent. The world pose of a node is the
product of the local transforms from the root down to it::

    world_from_node = world_from_parent @ T(translation) @ R(rotation) @ S(scaling)

Objects, agents and sensors each own a node; attaching one node under another (a camera under
an agent, an agent's node used as a robot object's root) makes the child follow the parent.
Nodes may carry :class:`Drawable` s (meshes the renderer draws with the node's world matrix).

Habitat semantics kept here: ``translate`` moves in the parent frame, and so does
``translate_local``: Habitat's nodes use Magnum's ``TranslationRotationScalingTransformation3D``,
which stores the translation apart from the rotation, so its ``translateLocal(v)`` is
``translation += v`` exactly like ``translate`` (Habitat's controls therefore pass parent-frame
axes: ``translate_local(node.transformation[2].xyz * d)``); ``rotate(angle, axis)``
pre-multiplies (rotation about the parent's axes),
``rotate_local`` post-multiplies (about the node's own axes); ``rotate_x/y/z`` are shorthands.
``transformation_matrix()`` is the absolute (world) transformation, as in Habitat.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from engine import mn
from engine.mn.matrices import rotation_and_scaling

if TYPE_CHECKING:  # pragma: no cover
    from engine.scene.assets import MeshData

__all__ = ["MIN_SCALING", "Drawable", "SceneGraph", "SceneNode"]

#: smallest scaling factor a node accepts on any axis: zero would collapse the node (its world
#: matrix could not be inverted to read a pose back) and a negative one would reflect it.
MIN_SCALING = 1e-9
#: 1, a transformation whose normalized rotation part R has ``|R^T R - I|`` above this in some
#: entry is a shear, not a rotation (refused by ``SceneNode.transformation``).
ORTHOGONALITY_TOLERANCE = 1e-4


@dataclass
class Drawable:
    """A mesh attached to a node: drawn by the renderer with the node's world matrix.

    ``lit`` False draws it flat whatever the lights; otherwise it is lit by the light setup
    named ``light_setup_key`` (:mod:`engine.gfx`; ``""`` is Habitat's
    ``DEFAULT_LIGHTING_KEY``, ``"no_lights"`` its flat ``NO_LIGHT_KEY``).
    ``semantic_id`` is written to the SEMANTIC sensor's id buffer.
    """

    mesh: MeshData
    lit: bool = True
    semantic_id: int = 0
    light_setup_key: str = ""


class SceneNode:
    """A node of the scene graph with a local TRS transform, a parent and children."""

    def __init__(self, parent: SceneNode | None = None, name: str = "") -> None:
        self.name = name
        self._parent: SceneNode | None = None
        self._children: list[SceneNode] = []
        self._translation = np.zeros(3)
        self._rotation = np.array([0.0, 0.0, 0.0, 1.0])  # [x, y, z, w]
        self._scaling = np.ones(3)
        self.drawables: list[Drawable] = []
        #: the sensor whose leaf node this is, by uuid (see :attr:`node_sensors`)
        self.own_sensors: dict[str, Any] = {}
        if parent is not None:
            self.parent = parent

    # -- hierarchy --------------------------------------------------------------------------
    @property
    def parent(self) -> SceneNode | None:
        return self._parent

    @parent.setter
    def parent(self, new_parent: SceneNode | None) -> None:
        """Re-parent the node, keeping its local transform (like Magnum's ``set_parent``)."""
        node = new_parent
        while node is not None:
            if node is self:
                raise ValueError("a scene node cannot be its own ancestor")
            node = node._parent
        if self._parent is not None:
            self._parent._children.remove(self)
        self._parent = new_parent
        if new_parent is not None:
            new_parent._children.append(self)

    @property
    def children(self) -> list[SceneNode]:
        return list(self._children)

    def create_child(self, name: str = "") -> SceneNode:
        """A new child node at the identity local transform (Habitat's ``create_child``)."""
        return SceneNode(self, name=name)

    def get_root_node(self) -> SceneNode:
        """The root of the graph this node belongs to (itself when it has no parent)."""
        node = self
        while node._parent is not None:
            node = node._parent
        return node

    def descendants(self) -> list[SceneNode]:
        """This node and every node below it, depth first (children in insertion order)."""
        nodes, stack = [], [self]
        while stack:
            node = stack.pop()
            nodes.append(node)
            stack.extend(reversed(node._children))
        return nodes

    @property
    def semantic_id(self) -> int:
        """The node's semantic id, written to the SEMANTIC buffer by the meshes it draws
        (Habitat's ``SceneNode.semantic_id``; not inherited by child nodes)."""
        return int(getattr(self, "_semantic_id", 0))

    @semantic_id.setter
    def semantic_id(self, value: Any) -> None:
        if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 0:
            raise ValueError(f"semantic_id must be a non-negative int, got {value!r}")
        self._semantic_id = int(value)
        for drawable in self.drawables:
            drawable.semantic_id = int(value)

    @property
    def node_sensors(self) -> dict[str, Any]:
        """The sensors of this node, by uuid (Habitat's ``node_sensors``): the one this leaf
        carries and those on its leaf children (``SensorFactory.create_sensors(node, ...)``
        puts each sensor on a new leaf child of ``node``). Computed from the graph on every
        read, so it follows nodes added and removed; a uuid met twice keeps the first
        sensor, as Habitat's sensor suites do."""
        sensors = dict(self.own_sensors)
        for child in self._children:
            for uuid, sensor in child.own_sensors.items():
                sensors.setdefault(uuid, sensor)
        return sensors

    @property
    def subtree_sensors(self) -> dict[str, Any]:
        """Every sensor on this node or below it, by uuid (Habitat's ``subtree_sensors``);
        computed from the graph on every read (an agent's ``sensors`` is this of its node),
        a uuid met twice keeps the first sensor created."""
        found: list[tuple[int, str, Any]] = []
        for node in self.descendants():
            for uuid, sensor in node.own_sensors.items():
                found.append((sensor.creation_order, uuid, sensor))
        sensors: dict[str, Any] = {}
        for _, uuid, sensor in sorted(found, key=lambda item: item[0]):
            sensors.setdefault(uuid, sensor)
        return sensors

    # -- local transform ----------------------------------------------------------------------
    @property
    def translation(self) -> mn.Vector3:
        return mn.Vector3(self._translation)

    @translation.setter
    def translation(self, value: Any) -> None:
        self._translation = np.asarray(mn.to_vector3(value, "translation"))

    @property
    def rotation(self) -> mn.Quaternion:
        return mn.Quaternion.from_xyzw(self._rotation)

    @rotation.setter
    def rotation(self, value: Any) -> None:
        self._rotation = mn.to_quaternion(value).xyzw

    @property
    def scaling(self) -> mn.Vector3:
        return mn.Vector3(self._scaling)

    @scaling.setter
    def scaling(self, value: Any) -> None:
        scaling = np.asarray(mn.to_vector3(value, "scaling"))
        if np.any(scaling < MIN_SCALING):
            raise ValueError(
                f"scaling must be >= {MIN_SCALING} on every axis (zero collapses "
                f"the node, negative reflects it), got {scaling.tolist()}"
            )
        self._scaling = scaling

    def local_matrix(self) -> np.ndarray:
        """``T @ R @ S`` as a (4, 4) ndarray."""
        matrix = np.eye(4)
        matrix[:3, :3] = mn.quaternion_to_matrix(self._rotation) * self._scaling  # R @ diag(s)
        matrix[:3, 3] = self._translation
        return matrix

    @property
    def transformation(self) -> mn.Matrix4:
        """The local transformation (relative to the parent)."""
        return mn.Matrix4(self.local_matrix())

    @transformation.setter
    def transformation(self, value: Any) -> None:
        """Decompose a rigid (optionally scaled) 4x4 matrix into translation, rotation, scaling."""
        rotation_matrix, scaling, translation = rotation_and_scaling(
            value, MIN_SCALING, ORTHOGONALITY_TOLERANCE
        )
        rotation = mn.matrix_to_quaternion(rotation_matrix)
        # q and -q are one rotation: keep the sign of the current rotation (no flips)
        self._rotation = -rotation if float(rotation @ self._rotation) < 0.0 else rotation
        self._translation = translation
        self._scaling = scaling

    # -- world transform ------------------------------------------------------------------------
    def world_matrix(self) -> np.ndarray:
        """``world_from_node`` as a (4, 4) ndarray (product of local matrices from the root)."""
        matrix = self.local_matrix()
        node = self._parent
        while node is not None:
            matrix = node.local_matrix() @ matrix
            node = node._parent
        return matrix

    def absolute_transformation(self) -> mn.Matrix4:
        return mn.Matrix4(self.world_matrix())

    def absolute_transformation_matrix(self) -> mn.Matrix4:
        """Habitat's (Magnum's) name: the node's transformation in the world frame."""
        return self.absolute_transformation()

    def transformation_matrix(self) -> mn.Matrix4:
        """Habitat's name for the absolute transformation."""
        return self.absolute_transformation()

    @property
    def absolute_translation(self) -> mn.Vector3:
        return mn.Vector3(self.world_matrix()[:3, 3])

    # -- Habitat's motion helpers ---------------------------------------------------------------
    def translate(self, vector: Any) -> SceneNode:
        """Move by ``vector`` given in the parent frame."""
        self._translation = self._translation + np.asarray(mn.to_vector3(vector, "vector"))
        return self

    def translate_local(self, vector: Any) -> SceneNode:
        """Move by ``vector``, not rotated by the node: the translation of a TRS transform is
        applied last, so Magnum (and Habitat) add a "local" translation in the parent frame,
        the same as :meth:`translate` (see the module docstring)."""
        return self.translate(vector)

    def rotate(self, angle: Any, axis: Any) -> SceneNode:
        """Rotate about ``axis`` of the parent frame: ``q <- r * q``."""
        turn = mn.Quaternion.rotation(angle, axis).xyzw
        self._rotation = _normalize(mn.quaternion_multiply(turn, self._rotation))
        return self

    def rotate_local(self, angle: Any, axis: Any) -> SceneNode:
        """Rotate about ``axis`` of this node's own frame: ``q <- q * r``."""
        turn = mn.Quaternion.rotation(angle, axis).xyzw
        self._rotation = _normalize(mn.quaternion_multiply(self._rotation, turn))
        return self

    def rotate_x(self, angle: Any) -> SceneNode:
        return self.rotate(angle, (1.0, 0.0, 0.0))

    def rotate_y(self, angle: Any) -> SceneNode:
        return self.rotate(angle, (0.0, 1.0, 0.0))

    def rotate_z(self, angle: Any) -> SceneNode:
        return self.rotate(angle, (0.0, 0.0, 1.0))

    def rotate_x_local(self, angle: Any) -> SceneNode:
        return self.rotate_local(angle, (1.0, 0.0, 0.0))

    def rotate_y_local(self, angle: Any) -> SceneNode:
        return self.rotate_local(angle, (0.0, 1.0, 0.0))

    def rotate_z_local(self, angle: Any) -> SceneNode:
        return self.rotate_local(angle, (0.0, 0.0, 1.0))

    @property
    def cumulative_bb(self) -> mn.Range3D:
        """Bounding box of the meshes of this node and all nodes below it, in this node's own
        frame (Habitat's ``cumulative_bb``); a zero box when nothing is drawn below it."""
        corners = []
        node_from_world = np.linalg.inv(self.world_matrix())
        for node in self.descendants():
            if not node.drawables:
                continue
            node_from_child = node_from_world @ node.world_matrix()
            for drawable in node.drawables:
                vertices = np.asarray(drawable.mesh.vertices, dtype=np.float64)
                if len(vertices):
                    # p_node = R p_child + t for every vertex of the mesh
                    corners.append(vertices @ node_from_child[:3, :3].T + node_from_child[:3, 3])
        if not corners:
            return mn.Range3D()
        return mn.Range3D.from_points(np.concatenate(corners))

    def reset_transformation(self) -> SceneNode:
        self._translation = np.zeros(3)
        self._rotation = np.array([0.0, 0.0, 0.0, 1.0])
        self._scaling = np.ones(3)
        return self

    def __repr__(self) -> str:
        label = f" {self.name!r}" if self.name else ""
        return f"<SceneNode{label} at {self.translation!r}>"


class SceneGraph:
    """Habitat's ``SceneGraph``: owns a root node; ``get_root_node().create_child()`` adds one.

    ``Simulator.get_active_scene_graph()`` returns the simulator's graph; a standalone
    ``SceneGraph()`` is what Habitat's agent tests build agents on.
    """

    def __init__(self, root: SceneNode | None = None) -> None:
        self._root = SceneNode(name="root") if root is None else root

    def get_root_node(self) -> SceneNode:
        return self._root

    def __repr__(self) -> str:
        return f"<SceneGraph with {len(self._root.descendants())} nodes>"


def _normalize(xyzw: np.ndarray) -> np.ndarray:
    return xyzw / np.linalg.norm(xyzw)
