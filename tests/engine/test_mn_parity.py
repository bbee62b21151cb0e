"""Magnum parity of ``engine.mn``: fuzzy equality, constructors, ``mn.math``, 2D types, colors.

The numbers follow Magnum's ``TypeTraits<Float>::equals`` (epsilon 1e-5: absolute near zero,
relative to ``|a| + |b|`` elsewhere) and the constructors of Magnum's Python bindings.
"""

import math

import numpy as np
import pytest

from engine import mn


# -- fuzzy equality -----------------------------------------------------------------------------
def test_vector_equality_is_fuzzy_relative_as_magnum():
    assert mn.Vector3(1.0, 2.0, 3.0) == mn.Vector3(1.0, 2.0, 3.0 + 1e-6)
    assert mn.Vector3(1.0, 2.0, 3.0) != mn.Vector3(1.0, 2.0, 3.001)
    # near zero the tolerance is absolute: 1e-6 vs 0 is equal, 1e-4 vs 0 is not
    assert mn.Vector3(0.0, 0.0, 0.0) == mn.Vector3(1e-6, 0.0, 0.0)
    assert mn.Vector3(0.0, 0.0, 0.0) != mn.Vector3(1e-4, 0.0, 0.0)
    # large magnitudes: relative, so 1e6 and 1e6 + 1 are equal (|d| / (|a| + |b|) = 5e-7)
    assert mn.Vector2(1e6, 0.0) == mn.Vector2(1e6 + 1.0, 0.0)
    assert mn.Vector2(1e6, 0.0) != mn.Vector2(1e6 + 100.0, 0.0)
    # infinities compare equal to themselves only
    assert mn.Vector2(math.inf, 0.0) == mn.Vector2(math.inf, 0.0)
    assert mn.Vector2(math.inf, 0.0) != mn.Vector2(-math.inf, 0.0)


def test_quaternion_and_matrix_equality_are_fuzzy():
    a = mn.Quaternion.rotation(mn.Deg(30.0), mn.Vector3.y_axis())
    b = mn.Quaternion.rotation(mn.Rad(math.radians(30.0) + 1e-7), mn.Vector3.y_axis())
    assert a == b
    assert a != -a  # the same rotation, but not the same quaternion (Magnum)
    assert a != mn.Quaternion.rotation(mn.Deg(31.0), mn.Vector3.y_axis())
    m = mn.Matrix4.rotation(mn.Deg(30.0), mn.Vector3.y_axis())
    assert m == mn.Matrix4.from_(b.to_matrix(), mn.Vector3())
    assert m != mn.Matrix4.rotation(mn.Deg(31.0), mn.Vector3.y_axis())


def test_integer_vectors_compare_exactly_and_truncate():
    assert mn.Vector2i(3, 5) == mn.Vector2i(3, 5)
    assert mn.Vector2i(3, 5) != mn.Vector2i(3, 6)
    assert mn.Vector2i(3, 5) / 2 == mn.Vector2i(1, 2)
    assert mn.Vector3i(1, 2, 3).z == 3 and isinstance(mn.Vector3i(1, 2, 3).x, int)
    with pytest.raises(ValueError):
        mn.Vector2i(1.5, 2)


def test_fuzzy_types_are_not_hashable_like_magnum():
    with pytest.raises(TypeError):
        hash(mn.Vector3())
    with pytest.raises(TypeError):
        hash(mn.Quaternion())


# -- constructors ----------------------------------------------------------------------------------
def test_quaternion_constructors_of_the_python_bindings():
    q_tuple = mn.Quaternion(((0.0, 0.70710678, 0.0), 0.70710678))
    q_pair = mn.Quaternion(mn.Vector3(0.0, 0.70710678, 0.0), 0.70710678)
    assert q_tuple == q_pair
    assert q_tuple == mn.Quaternion.rotation(mn.Deg(90.0), mn.Vector3.y_axis())
    assert mn.Quaternion() == mn.Quaternion.identity_init()
    pure = mn.Quaternion(mn.Vector3(1.0, 2.0, 3.0))  # Magnum: a vector alone has scalar 0
    assert pure.scalar == 0.0 and pure.vector == mn.Vector3(1.0, 2.0, 3.0)
    assert mn.Quaternion.zero_init().dot() == 0.0
    q = mn.Quaternion()
    q.scalar = 0.0
    q.vector = (1.0, 0.0, 0.0)
    assert q == mn.Quaternion.rotation(mn.Deg(180.0), mn.Vector3.x_axis())
    with pytest.raises(TypeError):
        mn.Quaternion(1.0, 2.0, 3.0)


def test_vectors_from_shorter_vectors_and_colors():
    assert mn.Vector3(mn.Vector2(1.0, 2.0), 3.0) == mn.Vector3(1.0, 2.0, 3.0)
    assert mn.Vector4(mn.Vector3(1.0, 2.0, 3.0), 4.0).w == 4.0
    assert mn.Color4(mn.Color3(1.0, 0.5, 0.0)) == mn.Color4(1.0, 0.5, 0.0, 1.0)
    assert mn.Color4(0.25).a == 1.0 and mn.Color4(0.25).r == 0.25
    assert mn.Color4(1.0, 0.0, 0.0, 0.5).rgb == mn.Color3.red()
    assert mn.Color3(0.1, 0.2, 0.3).g == pytest.approx(0.2)
    assert mn.Vector2(1.0, 0.0).perpendicular() == mn.Vector2(0.0, 1.0)


# -- mn.math ---------------------------------------------------------------------------------------
def test_math_constants_and_trigonometry():
    assert mn.math.pi == math.pi and mn.math.tau == 2 * math.pi
    assert mn.math.pi_half == math.pi / 2 and mn.math.sqrt_half == math.sqrt(0.5)
    assert mn.math.sin(mn.Deg(90.0)) == pytest.approx(1.0)
    assert mn.math.cos(mn.Rad(math.pi)) == pytest.approx(-1.0)
    assert isinstance(mn.math.acos(0.0), mn.Rad)
    assert float(mn.math.acos(0.0)) == pytest.approx(math.pi / 2)
    assert mn.math.sqrt(16.0) == 4.0


def test_math_vector_functions():
    x, y = mn.Vector3.x_axis(), mn.Vector3.y_axis()
    assert mn.math.cross(x, y) == mn.Vector3.z_axis()
    assert mn.math.dot(mn.Vector3(1, 2, 3), mn.Vector3(4, 5, 6)) == 32.0
    assert mn.math.cross(mn.Vector2(1.0, 0.0), mn.Vector2(0.0, 1.0)) == 1.0
    assert float(mn.math.angle(x, y)) == pytest.approx(math.pi / 2)
    assert mn.math.lerp(mn.Vector3(0, 0, 0), mn.Vector3(2, 4, 6), 0.5) == mn.Vector3(1, 2, 3)
    assert mn.math.lerp(1.0, 3.0, 0.25) == 1.5
    assert mn.math.lerp_inverted(1.0, 3.0, 1.5) == 0.25
    assert mn.math.clamp(mn.Vector3(-2, 0.5, 7), -1.0, 1.0) == mn.Vector3(-1, 0.5, 1)
    assert mn.math.round(2.5) == 3.0 and mn.math.round(-2.5) == -3.0  # half away from zero
    assert mn.math.sqrt(mn.Vector2(4.0, 9.0)) == mn.Vector2(2.0, 3.0)


def test_math_quaternion_interpolation():
    a = mn.Quaternion()
    b = mn.Quaternion.rotation(mn.Deg(90.0), mn.Vector3.y_axis())
    half = mn.math.slerp(a, b, 0.5)
    assert half == mn.Quaternion.rotation(mn.Deg(45.0), mn.Vector3.y_axis())
    assert float(mn.math.half_angle(a, b)) == pytest.approx(math.radians(45.0))
    # shortest path: -b is the same rotation; slerp_shortest_path goes the short way
    assert mn.math.slerp_shortest_path(a, -b, 0.5) == half
    assert mn.math.lerp(a, b, 0.5).is_normalized()


# -- 2D matrices and ranges ------------------------------------------------------------------------
def test_matrix3_is_a_2d_transformation():
    m = mn.Matrix3.translation(mn.Vector2(1.0, 2.0)) @ mn.Matrix3.rotation(mn.Deg(90.0))
    assert m.transform_point(mn.Vector2(1.0, 0.0)) == mn.Vector2(1.0, 3.0)
    assert m.transform_vector(mn.Vector2(1.0, 0.0)) == mn.Vector2(0.0, 1.0)
    assert m.translation == mn.Vector2(1.0, 2.0)
    assert m.inverted_rigid() @ m == mn.Matrix3()
    scale = mn.Matrix3.scaling(mn.Vector2(2.0, 3.0))
    assert scale.transform_point((1.0, 1.0)) == mn.Vector2(2.0, 3.0)


def test_range2d():
    r = mn.Range2D(mn.Vector2(0.0, 1.0), mn.Vector2(4.0, 3.0))
    assert r.size() == mn.Vector2(4.0, 2.0) and r.center() == mn.Vector2(2.0, 2.0)
    assert (r.left, r.right, r.bottom, r.top) == (0.0, 4.0, 1.0, 3.0)
    assert r.contains(mn.Vector2(1.0, 2.0)) and not r.contains(mn.Vector2(5.0, 2.0))
    assert mn.Range2D.from_size((0.0, 1.0), (4.0, 2.0)) == r
    assert mn.Range2D.from_center((2.0, 2.0), (2.0, 1.0)) == r
    np.testing.assert_array_equal(np.asarray(r.top_left), [0.0, 3.0])
