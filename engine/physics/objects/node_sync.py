"""Scene nodes and bodies: body poses go to the nodes after a step, user moves come back.

Habitat keeps a rigid object's pose in two places, the physics body and its scene node
(which the renderer and any child nodes such as an agent's sensors read). rigidsim does the
same, with the physics world as the truth for DYNAMIC objects:

* after every ``step_physics`` call, each moved body's pose is written to its root node as
  ``local = parent_world^-1 world`` (:meth:`NodeSync.write_nodes`);
* before every call, a KINEMATIC or STATIC object whose node the user moved (for example an
  agent node carrying an embodied robot) gets the node's world pose
  (:meth:`NodeSync.read_user_moves`).

A write is skipped when it would assign the very same numbers: the body has not moved since
the node's last write, and the node, its parent and the parent's pose are unchanged. Node
setters replace the stored arrays, so "unchanged" is checked by identity
(:class:`NodeStamp`). Nodes whose parent is a scene root at the origin (every object not
attached to another node) are written in one NumPy batch.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from engine import mn
from engine.mn.vectors import stable_norm

from ..core.bodies import DYNAMIC, STATIC, Bodies
from ..core.quaternions import matrix_to_quat, quat_to_matrix

_IDENTITY = np.eye(4)


def canonical_sign(q: np.ndarray) -> np.ndarray:
    """``(k, 4)`` quaternions with the sign Magnum's ``Quaternion.fromMatrix`` gives (Shepperd):
    ``w > 0`` when ``w^2 > 1/4`` (trace > 0), else the largest of ``|x|, |y|, |z|`` positive.

    Habitat writes a dynamic body's pose to its node through a matrix, so the quaternions it
    reports for DYNAMIC objects carry this sign (and Habitat's tests compare them with the
    sign-sensitive ``mn.math.angle``); kinematic and static ones keep the sign they were given.
    """
    rows = np.arange(len(q))
    largest = np.argmax(np.abs(q[:, :3]), axis=1)
    lead = np.where(q[:, 3] ** 2 > 0.25, q[:, 3], q[rows, largest])
    return np.where(lead[:, None] < 0.0, -q, q)


def same_sign_as(q: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """``q`` or ``-q`` (the same rotation), whichever lies in ``reference``'s hemisphere
    (``q . reference >= 0``): a quaternion read back from a matrix keeps its sign from step
    to step, as Habitat's does."""
    return -q if float(q @ reference) < 0.0 else q


class NodeStamp(NamedTuple):
    """What a node write used: the node's parent and transform arrays (by identity), the
    node world matrix it produced and the parent's world matrix (None without a parent)."""

    parent: Any
    translation: np.ndarray
    rotation: np.ndarray
    scaling: np.ndarray
    pose: np.ndarray
    parent_world: np.ndarray | None


class NodeSync:
    """Keeps the scene nodes of a world's bodies in step with them (module docstring).

    Holds the world's ``bodies`` and ``nodes`` (``{body index: root SceneNode}``) and its own
    state: ``_node_pose[index]`` the node world matrix last written or read back,
    ``_node_stamp[index]`` its :class:`NodeStamp`, ``_node_written_pose (n, 7)`` the body
    pose ``[x, q]`` of each node's last write (NaN: never written).
    """

    def __init__(self, bodies: Bodies, nodes: dict[int, Any]) -> None:
        self.bodies, self.nodes = bodies, nodes
        self._node_pose: dict[int, np.ndarray] = {}
        self._node_stamp: dict[int, NodeStamp] = {}
        self._node_written_pose = np.zeros((0, 7))

    # -- bodies -> nodes -------------------------------------------------------------------
    def write_nodes(self) -> None:
        """Write the pose of every body that can have moved to its root scene node."""
        b, n = self.bodies, self.bodies.count
        parent_cache: dict[int, tuple] = {}  # id(parent) -> (parent, world, inverse, local)
        pose = np.hstack([b.body_position[:n], b.body_rotation[:n]])
        moved = (pose != self._written_pose(n)).any(axis=1).tolist()  # since its last write
        under_root = []  # (index, node, parent) of nodes whose parent is a root at the origin
        skip = (~b.body_alive[:n] | (b.body_motion_type[:n] == STATIC)).tolist()
        identity_root: dict[int, bool] = {}  # id(parent) -> a root at the origin
        same_world: dict[tuple[int, int], tuple] = {}  # parent matrices compared this pass
        for index, node in list(self.nodes.items()):
            if skip[index]:
                continue
            if not moved[index] and self._node_unchanged(index, parent_cache, same_world):
                continue
            parent = node._parent  # (the ``parent`` property's field: one lookup per node)
            if (
                parent is not None
                and parent._parent is None
                and self._is_identity_root(parent, parent_cache, identity_root)
            ):
                under_root.append((index, node, parent))
            else:
                self.write_node(index, parent_cache)
        if under_root:
            self._write_root_children(under_root)

    def _is_identity_root(self, parent, parent_cache: dict, known: dict) -> bool:
        """True when ``parent``'s world matrix is the identity (answer kept per pass)."""
        if id(parent) not in known:
            known[id(parent)] = np.array_equal(
                self._parent_matrices(parent, parent_cache)[0], _IDENTITY
            )
        return known[id(parent)]

    def _write_root_children(self, children: list[tuple[int, Any, Any]]) -> None:
        """:meth:`write_node` for nodes whose parent is an identity root, all at once;
        ``children`` holds ``(body index, node, parent)`` of each.

        Their local transform is the body pose itself (``local = I^-1 world``), so the
        node gets the body's translation and quaternion, and its world matrix is
        ``[R diag(s) | x]`` for its own scaling ``s``.
        """
        b = self.bodies
        index_list, nodes, parents = zip(*children, strict=True)
        indices = np.array(index_list, dtype=np.int64)
        position, rotation = b.body_position[indices], b.body_rotation[indices]
        scaling = np.array([node._scaling for node in nodes])
        pose = np.zeros((len(indices), 4, 4))
        pose[:, :3, :3] = quat_to_matrix(rotation) * scaling[:, None, :]  # R diag(s)
        pose[:, :3, 3], pose[:, 3, 3] = position, 1.0
        self._written_pose(int(indices.max()) + 1)[indices] = np.hstack([position, rotation])
        # dynamic bodies: the sign a matrix round trip gives, as Habitat's nodes show it
        dynamic = b.body_motion_type[indices] == DYNAMIC
        rotation = np.where(dynamic[:, None], canonical_sign(rotation), rotation)
        # iterating the (k, ...) arrays yields the row views position[k], ... in one loop
        for index, node, parent, x, q, matrix in zip(
            index_list, nodes, parents, position, rotation, pose, strict=True
        ):
            node._translation, node._rotation = x, q
            self._node_pose[index] = matrix
            self._node_stamp[index] = NodeStamp(parent, x, q, node._scaling, matrix, _IDENTITY)

    def write_node(self, index: int, parent_cache: dict | None = None) -> None:
        """Write body ``index``'s pose to its node: ``local = parent_world^-1 world``.

        ``parent_cache`` (optional) shares each parent's matrices across one pass over all
        nodes; a write that would repeat the last one is skipped (module docstring).
        """
        node = self.nodes.get(index)
        if node is None:
            return
        b = self.bodies
        if self._body_unmoved(index) and self._node_unchanged(index, parent_cache):
            return
        parent = node.parent
        parent_world = parent_inv = parent_local = None
        if parent is not None:
            parent_world, parent_inv, parent_local = self._parent_matrices(parent, parent_cache)
        world = np.eye(4)
        world[:3, :3] = quat_to_matrix(b.body_rotation[index])
        world[:3, 3] = b.body_position[index]
        if self._node_pose.get(index) is not None and np.array_equal(self._node_pose[index], world):
            return
        local = world if parent_inv is None else parent_inv @ world
        node.translation = local[:3, 3]
        rotation = matrix_to_quat(local[:3, :3])  # Magnum's fromMatrix sign
        if b.body_motion_type[index] != DYNAMIC:  # kinematic / static: no sign flips
            rotation = same_sign_as(rotation, node._rotation)
        node.rotation = mn.Quaternion.from_xyzw(rotation)
        if parent is not None and parent._parent is None:
            pose = parent_local @ node.local_matrix()  # what node.world_matrix() computes
        else:
            pose = node.world_matrix().copy()
        self._node_pose[index] = pose
        self._written_pose(index + 1)[index] = np.concatenate(
            [b.body_position[index], b.body_rotation[index]]
        )
        self._node_stamp[index] = NodeStamp(
            parent, node._translation, node._rotation, node._scaling, pose, parent_world
        )

    def _written_pose(self, n: int) -> np.ndarray:
        """``(n, 7)`` body pose [x, q] at each node's last write (NaN: never written)."""
        if len(self._node_written_pose) < n:
            grown = np.full((max(n, 2 * len(self._node_written_pose)), 7), np.nan)
            grown[: len(self._node_written_pose)] = self._node_written_pose
            self._node_written_pose = grown
        return self._node_written_pose[:n]

    def _body_unmoved(self, index: int) -> bool:
        """True when body ``index`` has the pose of its node's last write."""
        b = self.bodies
        written = self._written_pose(index + 1)[index]
        return bool(
            np.all(written[:3] == b.body_position[index])
            and np.all(written[3:] == b.body_rotation[index])
        )

    def _node_unchanged(
        self, index: int, parent_cache: dict | None, same_world: dict | None = None
    ) -> bool:
        """True when body ``index``'s node, its parent and the parent's pose are as they were
        at the node's last write (checked by identity: setters replace the stored objects).
        ``same_world`` (with ``parent_cache``) keeps each comparison of a recorded parent
        matrix with the parent's current one for the pass: the nodes under one parent
        mostly recorded the same matrix, so it is compared once."""
        last, node = self._node_stamp.get(index), self.nodes[index]
        if last is None or node.parent is not last.parent:
            return False
        if (
            node._translation is not last.translation
            or node._rotation is not last.rotation
            or node._scaling is not last.scaling
            or self._node_pose.get(index) is not last.pose
        ):
            return False
        if node.parent is None:
            return last.parent_world is None
        if last.parent_world is None:
            return False
        world = self._parent_matrices(node.parent, parent_cache)[0]
        if same_world is None or parent_cache is None:
            return bool(np.array_equal(last.parent_world, world))
        key = (id(last.parent_world), id(world))
        if key not in same_world:  # (the entry keeps both arrays alive: ids stay unique)
            same = bool(np.array_equal(last.parent_world, world))
            same_world[key] = (last.parent_world, world, same)
        return same_world[key][2]

    @staticmethod
    def _parent_matrices(parent, cache: dict | None):
        """``(world, world^-1, local)`` matrices of a parent node (cached within one pass)."""
        if cache is not None and id(parent) in cache:
            return cache[id(parent)][1:]
        world = parent.world_matrix()
        entry = (parent, world, np.linalg.inv(world), parent.local_matrix())
        if cache is not None:
            cache[id(parent)] = entry  # the parent is kept alive, so its id stays unique
        return entry[1:]

    def forget(self, index: int) -> None:
        """Drop what is known about body ``index``'s node: the next write rewrites it."""
        self._node_pose.pop(index, None)
        self._node_stamp.pop(index, None)
        if index < len(self._node_written_pose):
            self._node_written_pose[index] = np.nan  # never written (a reused slot rewrites)

    # -- nodes -> bodies -------------------------------------------------------------------
    def read_user_moves(self) -> list[int]:
        """Read back user-moved nodes of KINEMATIC and STATIC objects into their bodies;
        returns the indices of the bodies moved (their fcl objects and neighbors need it).
        Every node is checked before any body changes."""
        b, n = self.bodies, self.bodies.count
        moved = []  # (index, world matrix, rotation): all checked before any body changes
        skip = (~b.body_alive[:n] | (b.body_motion_type[:n] == DYNAMIC)).tolist()
        for index, node in self.nodes.items():
            if skip[index]:
                continue
            world = node.world_matrix()
            last = self._node_pose.get(index)
            if last is not None and np.array_equal(world, last):
                continue
            scale = stable_norm(world[:3, :3], axis=0)
            if not (np.all(np.isfinite(world)) and np.all(scale > 0.0)):
                raise ValueError(
                    f"the scene node of object {index} has a non-finite or "
                    f"degenerate world transform; no body was moved"
                )
            moved.append((index, world, world[:3, :3] / scale))
        for index, world, rotation in moved:
            b.body_position[index] = world[:3, 3]
            # q and -q are one rotation: keep the sign of the last step (no q -> -q flips)
            b.body_rotation[index] = same_sign_as(matrix_to_quat(rotation), b.body_rotation[index])
            self._node_pose[index] = world.copy()
        return [index for index, _, _ in moved]
