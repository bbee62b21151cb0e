"""Habitat's quaternion helpers return what Habitat returns (numpy-quaternion, or Magnum for
``quat_to_magnum`` / ``random_quaternion``), with the behaviour of Habitat's own tests."""

import math

import numpy as np
import pytest
import quaternion as qt

from engine import mn
from engine.utils import common
from engine.utils.common.quaternion_utils import (
    angle_between_quats,
    quat_from_angle_axis,
    quat_from_coeffs,
    quat_from_magnum,
    quat_from_two_vectors,
    quat_rotate_vector,
    quat_to_angle_axis,
    quat_to_coeffs,
    quat_to_magnum,
    random_quaternion,
)


def test_coeffs_are_imaginary_first_and_round_trip():
    q = quat_from_coeffs(np.array([1.0, 2.0, 3.0, 4.0]))
    assert isinstance(q, qt.quaternion)
    assert q.real == 4.0
    np.testing.assert_array_equal(q.imag, [1.0, 2.0, 3.0])
    zero = quat_from_coeffs([0.0, 0.0, 0.0, 0.0])  # Habitat does not normalize
    assert zero.real == 0.0 and not zero.imag.any()
    coeffs = np.array([0.1, 0.2, 0.3, 0.9]) / np.linalg.norm([0.1, 0.2, 0.3, 0.9])
    np.testing.assert_allclose(quat_to_coeffs(quat_from_coeffs(coeffs)), coeffs)
    assert quat_to_coeffs(qt.quaternion(1, 0, 0, 0)).shape == (4,)


def test_magnum_conversions():
    q = qt.quaternion(0.5, 0.5, 0.5, 0.5)
    magnum = quat_to_magnum(q)
    assert isinstance(magnum, mn.Quaternion)
    assert magnum.scalar == 0.5 and magnum.vector == mn.Vector3(0.5, 0.5, 0.5)
    assert quat_from_magnum(magnum) == q
    assert isinstance(quat_from_magnum(mn.Quaternion()), qt.quaternion)


@pytest.mark.parametrize(
    "angle, axis",
    [
        (math.pi / 2, [1.0, 0.0, 0.0]),
        (math.pi / 2, [0.0, 1.0, 0.0]),
        (math.pi, [1.0, 0.0, 0.0]),
        (0.1, [0.0, 0.0, 1.0]),
    ],
)
def test_angle_axis_round_trip(angle, axis):
    theta, axis_out = quat_to_angle_axis(quat_from_angle_axis(angle, np.array(axis)))
    assert theta == pytest.approx(angle, abs=1e-5)
    np.testing.assert_allclose(np.abs(axis_out), np.abs(axis), atol=1e-5)


def test_identity_angle_axis_is_zero_about_x_and_axes_are_normalized():
    theta, axis = quat_to_angle_axis(qt.quaternion(1, 0, 0, 0))
    assert theta == 0.0
    np.testing.assert_array_equal(axis, [1.0, 0.0, 0.0])
    assert quat_from_angle_axis(math.pi / 4, np.array([2.0, 0.0, 0.0])).norm() == pytest.approx(1)
    with pytest.raises(ValueError):
        quat_from_angle_axis(1.0, [0.0, 0.0, 0.0])


@pytest.mark.parametrize(
    "v0, v1",
    [
        ([1.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
        ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ([1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]),
        ([3.0, 0.0, 0.0], [0.0, 5.0, 0.0]),
        ([1.0, 2.0, 3.0], [-2.0, 1.0, 0.5]),
    ],
)
def test_quat_from_two_vectors_rotates_v0_onto_v1(v0, v1):
    q = quat_from_two_vectors(np.array(v0), np.array(v1))
    assert q.norm() == pytest.approx(1.0, abs=1e-5)
    rotated = quat_rotate_vector(q, np.array(v0) / np.linalg.norm(v0))
    np.testing.assert_allclose(rotated, np.array(v1) / np.linalg.norm(v1), atol=1e-5)


def test_angle_between_quats_accepts_magnum_and_numpy_quaternions():
    identity = mn.Quaternion.identity_init()
    quarter = mn.Quaternion.rotation(mn.Deg(90.0), mn.Vector3.y_axis())
    assert angle_between_quats(identity, identity) == pytest.approx(0.0, abs=1e-6)
    assert angle_between_quats(identity, quarter) == pytest.approx(math.pi / 2, abs=1e-4)
    half = mn.Quaternion.rotation(mn.Deg(180.0), mn.Vector3.y_axis())
    assert angle_between_quats(identity, half) == pytest.approx(math.pi, abs=1e-4)
    a = quat_from_magnum(mn.Quaternion.rotation(mn.Deg(30.0), mn.Vector3.x_axis()))
    b = quat_from_magnum(mn.Quaternion.rotation(mn.Deg(75.0), mn.Vector3.y_axis()))
    assert angle_between_quats(a, b) == pytest.approx(angle_between_quats(b, a), abs=1e-9)
    assert angle_between_quats(a, -a) == pytest.approx(0.0, abs=1e-7)  # q and -q: same


def test_quat_rotate_vector():
    z_quarter = quat_from_angle_axis(math.pi / 2, np.array([0.0, 0.0, 1.0]))
    np.testing.assert_allclose(
        quat_rotate_vector(z_quarter, [1.0, 0.0, 0.0]), [0, 1, 0], atol=1e-12
    )
    q = quat_from_angle_axis(1.23, np.array([1.0, 1.0, 1.0]))
    assert np.linalg.norm(quat_rotate_vector(q, [3.0, 4.0, 0.0])) == pytest.approx(5.0)
    np.testing.assert_array_equal(
        quat_rotate_vector(qt.quaternion(1, 0, 0, 0), [1, 2, 3]), [1, 2, 3]
    )


def test_random_quaternion_is_a_unit_magnum_quaternion_driven_by_np_random():
    np.random.seed(3)
    first = random_quaternion()
    assert isinstance(first, mn.Quaternion)
    assert first.length() == pytest.approx(1.0, abs=1e-12)
    np.random.seed(3)
    assert random_quaternion() == first
    assert random_quaternion() != first


def test_common_reexports_the_helpers():
    assert common.quat_from_coeffs is quat_from_coeffs
    assert common.angle_between_quats is angle_between_quats
    from engine.utils import quat_from_angle_axis as top_level

    assert top_level is quat_from_angle_axis
