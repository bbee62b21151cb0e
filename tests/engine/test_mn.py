"""The magnum-like math module: Magnum's semantics and quirks the tutorials rely on."""

import math

import numpy as np
import pytest

from engine import mn


def test_vector3_dot_without_argument_is_squared_length():
    v = mn.Vector3(1.0, 2.0, 2.0)
    assert v.dot() == 9.0  # Magnum quirk: squared length, not length
    assert v.length() == 3.0
    assert v.dot([1, 0, 0]) == 1.0


def test_vector3_mixes_with_lists_and_arrays():
    v = mn.Vector3([1.0, 2.0, 3.0])
    assert isinstance(v + [1, 1, 1], mn.Vector3)
    assert (v + [1, 1, 1]) == [2, 3, 4]
    assert (np.array([1.0, 1.0, 1.0]) + v) == [2, 3, 4]
    assert (v * 5) == [5, 10, 15] and (5 * v) == [5, 10, 15]
    assert (-1.0 * v) == [-1, -2, -3]
    assert v.x == 1 and v.y == 2 and v.z == 3
    np.testing.assert_array_equal(np.asarray(v), [1, 2, 3])
    np.testing.assert_allclose(np.asarray(v.normalized()), np.array([1, 2, 3]) / math.sqrt(14))


def test_vector3_wrong_shape_raises():
    with pytest.raises(ValueError):
        mn.Vector3([1.0, 2.0])


def test_deg_rad_conversions():
    assert float(mn.Rad(mn.Deg(180.0))) == pytest.approx(math.pi, abs=1e-15)
    assert float(mn.Deg(mn.Rad(math.pi / 2))) == pytest.approx(90.0)


def test_quaternion_rotation_about_minus_x_matches_magnum():
    q = mn.Quaternion.rotation(mn.Deg(90.0), [-1.0, 0.0, 0.0])
    np.testing.assert_allclose(np.asarray(q.vector), [-math.sqrt(0.5), 0, 0], atol=1e-12)
    assert q.scalar == pytest.approx(math.sqrt(0.5))
    # rotating +Y by 90 degrees about -X gives -Z
    np.testing.assert_allclose(np.asarray(q.transform_vector([0, 1, 0])), [0, 0, -1], atol=1e-12)


def test_quaternion_products_compose_rotations():
    a = mn.Quaternion.rotation(mn.Rad(0.3), [0, 1, 0])
    b = mn.Quaternion.rotation(mn.Rad(0.2), [0, 1, 0])
    c = a * b
    assert float(c.angle()) == pytest.approx(0.5)
    m = np.asarray(a.to_matrix()) @ np.asarray(b.to_matrix())
    np.testing.assert_allclose(np.asarray(c.to_matrix()), m, atol=1e-12)
    inv = c.inverted()
    np.testing.assert_allclose((c * inv).xyzw, [0, 0, 0, 1], atol=1e-12)


def test_quaternion_matrix_round_trip_for_many_rotations():
    rng = np.random.default_rng(0)
    for _ in range(50):
        xyzw = rng.normal(size=4)
        q = mn.Quaternion.from_xyzw(xyzw / np.linalg.norm(xyzw))
        back = mn.Quaternion.from_matrix(q.to_matrix())
        # q and -q are the same rotation
        assert min(np.abs(back.xyzw - q.xyzw).max(), np.abs(back.xyzw + q.xyzw).max()) < 1e-12


def test_to_quaternion_accepts_numpy_quaternion_like_and_xyzw_lists():
    class FakeNpQuaternion:  # np.quaternion(w, x, y, z) exposes these attributes
        w, x, y, z = -0.83147, 0.0, 0.55557, 0.0

    q = mn.to_quaternion(FakeNpQuaternion())
    assert q.scalar == pytest.approx(-0.83147 / math.hypot(0.83147, 0.55557))
    q2 = mn.to_quaternion([0.0, 0.0, 0.0, 2.0])  # [x, y, z, w], normalized
    np.testing.assert_array_equal(q2.xyzw, [0, 0, 0, 1])
    for bad in ([np.nan, 0, 0, 1], [0, 0, 0, 0], [1, 2, 3], None, "q"):
        with pytest.raises(ValueError):
            mn.to_quaternion(bad)


def test_to_vector3_rejects_nan_inf_and_wrong_shapes_naming_the_value():
    with pytest.raises(ValueError, match="translation"):
        mn.to_vector3([np.nan, 0, 0], "translation")
    with pytest.raises(ValueError, match="finite"):
        mn.to_vector3([np.inf, 0, 0])
    with pytest.raises(ValueError, match="shape"):
        mn.to_vector3([0, 0])
    with pytest.raises(ValueError):
        mn.to_vector3(None)


def test_matrix4_translation_is_both_constructor_and_accessor():
    m = mn.Matrix4.translation([1.0, 2.0, 3.0])
    assert m.translation == [1, 2, 3]
    r = mn.Matrix4.rotation(mn.Deg(90.0), [0, 1, 0])
    np.testing.assert_allclose(np.asarray(r.transform_point([1, 0, 0])), [0, 0, -1], atol=1e-12)
    composed = m @ r
    moved = composed.transform_point([1, 0, 0])
    np.testing.assert_allclose(np.asarray(moved), [1, 2, 2], atol=1e-12)
    np.testing.assert_allclose(np.asarray(composed.inverted() @ composed), np.eye(4), atol=1e-12)
    turned = (m * r).transform_vector([1, 0, 0])
    np.testing.assert_allclose(np.asarray(turned), [0, 0, -1], atol=1e-12)
    rebuilt = mn.Matrix4.from_(r.rotation(), [1, 2, 3])
    np.testing.assert_allclose(np.asarray(rebuilt), np.asarray(composed), atol=1e-12)


def test_range3d_size_center_contains():
    box = mn.Range3D([-1, 0, 2], [1, 2, 4])
    assert box.size() == [2, 2, 2] and box.center() == [0, 1, 3]
    assert box.contains([0, 1, 3]) and not box.contains([0, 3, 3])
