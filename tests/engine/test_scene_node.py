"""Scene graph: TRS composition and Habitat's translate/rotate semantics."""

import math

import numpy as np
import pytest

from engine import mn
from engine.scene.graph import SceneNode


def test_child_world_matrix_is_parent_times_local():
    root = SceneNode()
    parent = SceneNode(root)
    parent.translation = [1.0, 0.0, 0.0]
    parent.rotation = mn.Quaternion.rotation(mn.Deg(90.0), [0, 1, 0])
    child = SceneNode(parent)
    child.translation = [0.0, 0.0, -1.0]
    # the child sits 1 m along the parent's -Z, which the parent's 90 degree yaw turns to -X
    np.testing.assert_allclose(np.asarray(child.absolute_translation), [0, 0, 0], atol=1e-12)
    np.testing.assert_allclose(
        np.asarray(child.transformation_matrix()),
        parent.local_matrix() @ child.local_matrix(),
        atol=1e-12,
    )


def test_translate_local_adds_its_vector_in_the_parent_frame_as_magnums_trs_nodes_do():
    """Habitat's nodes are Magnum TRS objects: ``translateLocal(v)`` is ``translation += v``,
    not rotated by the node. Habitat's controls rely on it: they pass the node's axis in the
    parent frame, ``transformation[2].xyz``, and the agent moves along its own -Z once."""
    node = SceneNode()
    node.rotate_y(mn.Deg(90.0))  # the node's -Z (forward) is the world's -X
    node.translate_local([0, 0, -1])
    np.testing.assert_allclose(np.asarray(node.translation), [0, 0, -1], atol=1e-12)
    forward = -np.asarray(node.transformation)[:3, 2]  # Habitat: -transformation[2].xyz
    np.testing.assert_allclose(forward, [-1, 0, 0], atol=1e-12)
    node.translate_local(forward)  # a step forward, as default and noisy controls take it
    np.testing.assert_allclose(np.asarray(node.translation), [-1, 0, -1], atol=1e-12)
    node.translate([0, 1, 0])
    np.testing.assert_allclose(np.asarray(node.translation), [-1, 1, -1], atol=1e-12)


def test_rotate_pre_multiplies_and_rotate_local_post_multiplies():
    a, b = SceneNode(), SceneNode()
    q_first = mn.Quaternion.rotation(mn.Deg(90.0), [1, 0, 0])
    a.rotation = b.rotation = q_first
    a.rotate(mn.Deg(90.0), [0, 1, 0])
    b.rotate_local(mn.Deg(90.0), [0, 1, 0])
    turn = mn.Quaternion.rotation(mn.Deg(90.0), [0, 1, 0])
    np.testing.assert_allclose(a.rotation.xyzw, (turn * q_first).xyzw, atol=1e-12)
    np.testing.assert_allclose(b.rotation.xyzw, (q_first * turn).xyzw, atol=1e-12)


def test_properties_return_copies_so_augmented_assignment_uses_setter():
    node = SceneNode()
    t = node.translation
    t.x = 5.0
    assert node.translation == [0, 0, 0]
    node.translation += [0, 0, 0.01]
    assert node.translation == [0, 0, 0.01]


def test_transformation_setter_decomposes_scaled_rigid_matrix():
    node = SceneNode()
    rot = mn.Quaternion.rotation(mn.Rad(0.7), mn.Vector3(1, 2, 3).normalized())
    matrix = mn.Matrix4.from_(np.asarray(rot.to_matrix()) * 2.0, [1, 2, 3])
    node.transformation = matrix
    np.testing.assert_allclose(np.asarray(node.scaling), [2, 2, 2], atol=1e-12)
    np.testing.assert_allclose(node.local_matrix(), np.asarray(matrix), atol=1e-12)


def test_reparenting_and_cycles():
    root, a = SceneNode(), SceneNode()
    a.parent = root
    assert a in root.children
    with pytest.raises(ValueError):
        root.parent = a
    a.parent = None
    assert root.children == []


def test_bad_input_leaves_node_unchanged():
    node = SceneNode()
    node.translation = [1, 2, 3]
    with pytest.raises(ValueError):
        node.translation = [math.nan, 0, 0]
    with pytest.raises(ValueError):
        node.rotation = [0, 0, 0, 0]
    assert node.translation == [1, 2, 3]
    np.testing.assert_array_equal(node.rotation.xyzw, [0, 0, 0, 1])
