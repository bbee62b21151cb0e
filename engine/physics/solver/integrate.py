"""Time integration: symplectic (semi-implicit) Euler for translation, and a rotation update
that conserves angular momentum exactly and never gains kinetic energy.

Velocity stage (before the contact solver), for every awake dynamic body::

    v <- v + h (g + F / m)                       (Newton, explicit in the force)
    w <- w + h I_w^-1 tau,  I_w = R I_body R^T   (Euler's equation without the gyroscopic term)
    v <- v (1 - d_lin)^h,   w <- w (1 - d_ang)^h (Bullet / Habitat damping)

Position stage (after the solver): ``x <- x + h v`` (so free fall follows the discrete
recurrence ``x_{n+1} = x_n + h (v_n + h g)``). Rotation carries the gyroscopic effect
implicitly: the world angular momentum ``L = I_w(q_n) w_n`` is held fixed while the body
turns, ``q_{n+1} = exp(h w_mid) q_n`` with ``w_mid = I_w(q_half)^-1 L`` evaluated at the
half-step orientation, and the new velocity is ``w_{n+1} = I_w(q_{n+1})^-1 L``. If the
kinetic energy ``E = L . w / 2`` would rise, ``w`` is scaled down to the old energy
(so a free spin never gains energy). See Catto, "Numerical Methods", GDC 2015, for why
an explicit gyroscopic term blows up at 1/60 s.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from engine.mn.vectors import stable_norm

from ..core import settings
from ..core.bodies import DYNAMIC
from ..core.quaternions import quat_multiply, quat_to_matrix, rotation_quat, vector_length

if TYPE_CHECKING:
    from ..core.bodies import Bodies


def awake_dynamic_bodies(bodies: Bodies) -> np.ndarray:
    """``(k,)`` indices of the bodies the step moves: alive, awake and DYNAMIC."""
    n = bodies.count
    mask = bodies.body_alive[:n] & bodies.body_awake[:n] & (bodies.body_motion_type[:n] == DYNAMIC)
    return np.nonzero(mask)[0]


def body_velocities(bodies: Bodies) -> np.ndarray:
    """``(n, 6)`` copy of every body's [v, w] (world frame, m/s and rad/s)."""
    n = bodies.count
    return np.concatenate([bodies.body_linear_velocity[:n], bodies.body_angular_velocity[:n]], 1)


def integrate_stage(
    bodies: Bodies, moving: np.ndarray, pseudo_velocity: np.ndarray | None, h: float
) -> None:
    """Stage 4 of the step: clamp speeds, advance the poses of ``moving (k,)`` by ``h``
    (plus the split-impulse ``pseudo_velocity (n, 6)``), then sweep fast bodies (CCD-lite)."""
    from .sweep import sweep_fast_bodies

    clamp_speeds(bodies, moving, settings.MAX_LINEAR_SPEED, settings.MAX_ANGULAR_SPEED)
    old_position = bodies.body_position[moving]  # (an index array's read is a copy)
    old_rotation = bodies.body_rotation[moving]
    extra_linear = None if pseudo_velocity is None else pseudo_velocity[moving, :3]
    # the split-impulse turn obeys the angular speed limit too: with a tiny inertia (a 1 kg
    # cube given 1e-300 kg m^2) its I^-1 lambda would overflow the rotation to NaN
    extra_angular = (
        None
        if pseudo_velocity is None
        else clamp_rows(pseudo_velocity[moving, 3:], settings.MAX_ANGULAR_SPEED)
    )
    integrate_positions(bodies, moving, h, extra_linear, extra_angular)
    sweep_fast_bodies(bodies, moving, old_position, old_rotation)


def world_inverse_inertia(rotation: np.ndarray, inertia: np.ndarray) -> np.ndarray:
    """``(k, 3, 3)`` world inverse inertia ``R diag(1/I) R^T`` from quaternions ``(k, 4)``."""
    return _inverse_inertia(quat_to_matrix(rotation), 1.0 / np.maximum(inertia, settings.TINY))


def _inverse_inertia(r: np.ndarray, inv_diag: np.ndarray) -> np.ndarray:
    """``(k, 3, 3)`` ``R diag(1/I) R^T`` of rotation matrices ``r (k, 3, 3)`` and the
    inverse principal inertias ``inv_diag (k, 3)``."""
    # I_w^-1[i, j] = sum_k R[i, k] / I_k R[j, k]
    return (r * inv_diag[:, None, :]) @ r.swapaxes(1, 2)


def integrate_velocities(bodies, index: np.ndarray, gravity: np.ndarray, h: float) -> None:
    """Apply gravity, forces, torques and damping to the bodies ``index`` (awake, dynamic)."""
    if len(index) == 0:
        return
    mass = bodies.body_mass[index][:, None]
    lin = (1.0 - bodies.body_linear_damping[index]) ** h
    ang = (1.0 - bodies.body_angular_damping[index]) ** h
    # v += h (g + F / m), then v *= (1 - d)^h: read and written back once
    v = bodies.body_linear_velocity[index]
    v += h * (gravity + bodies.body_force[index] / mass)
    v *= lin[:, None]
    bodies.body_linear_velocity[index] = v
    # w += h I_w^-1 tau, then w *= (1 - d)^h
    w = bodies.body_angular_velocity[index]
    w += h * _angular_acceleration(bodies, index)
    w *= ang[:, None]
    bodies.body_angular_velocity[index] = w


def _angular_acceleration(bodies, index: np.ndarray) -> np.ndarray:
    """``(k, 3)`` ``I_w^-1 tau`` of the bodies ``index``: zeros without a torque (the usual
    case), so the world inverse inertia is only built when some body has one."""
    torque = bodies.body_torque[index]
    if not torque.any():
        return np.zeros_like(torque)
    inv_inertia = world_inverse_inertia(bodies.body_rotation[index], bodies.body_inertia[index])
    return np.einsum("kij,kj->ki", inv_inertia, torque)


def clamp_speeds(bodies, index: np.ndarray, max_linear: float, max_angular: float) -> None:
    """Scale velocities so ``|v| <= max_linear`` and ``|w| <= max_angular``."""
    for name, limit in (
        ("body_linear_velocity", max_linear),
        ("body_angular_velocity", max_angular),
    ):
        velocity = getattr(bodies, name)[index]
        clamped = clamp_rows(velocity, limit)
        if clamped is not velocity:
            getattr(bodies, name)[index] = clamped


def clamp_rows(velocity: np.ndarray, limit: float) -> np.ndarray:
    """``velocity (k, 3)`` with each row scaled to ``|row| <= limit``; the same array when
    no row needs it."""
    # every component finite and below limit / 2 (so |v| < 0.87 limit): the scale would
    # be exactly 1 (NaN fails the test and takes the full path below)
    if np.abs(velocity).max(initial=0.0) < 0.5 * limit:
        return velocity
    speed = stable_norm(velocity, axis=1)  # |v| without overflow above 1e154 m/s
    scale = np.minimum(1.0, limit / np.maximum(speed, settings.TINY))
    return velocity * scale[:, None]


def integrate_positions(
    bodies, index: np.ndarray, h: float, linear_extra=None, angular_extra=None
) -> None:
    """Advance poses of ``index`` by one step ``h`` (see module docstring).

    ``linear_extra`` / ``angular_extra`` ``(k, 3)`` are split-impulse pseudo velocities that
    move the body without entering its stored velocity.
    """
    if len(index) == 0:
        return
    v = bodies.body_linear_velocity[index]
    w = bodies.body_angular_velocity[index]
    q = bodies.body_rotation[index]
    inertia = bodies.body_inertia[index]
    bodies.body_position[index] += h * (v if linear_extra is None else v + linear_extra)
    r = quat_to_matrix(q)
    # L = R I R^T w  (world angular momentum, held constant over the step)
    momentum = np.einsum("kij,kj->ki", r, inertia * np.einsum("kji,kj->ki", r, w))
    energy_old = 0.5 * np.add.reduce(momentum * w, axis=1)
    inv_diag = 1.0 / np.maximum(inertia, settings.TINY)  # 1 / I, for I_w^-1 at two poses
    q_half = _normalize(quat_multiply(rotation_quat(0.5 * h * w), q))
    w_mid = np.einsum("kij,kj->ki", _inverse_inertia(quat_to_matrix(q_half), inv_diag), momentum)
    turn = w_mid if angular_extra is None else w_mid + angular_extra
    q_new = _normalize(quat_multiply(rotation_quat(h * turn), q))
    w_new = np.einsum("kij,kj->ki", _inverse_inertia(quat_to_matrix(q_new), inv_diag), momentum)
    energy_new = 0.5 * np.add.reduce(momentum * w_new, axis=1)
    # never gain energy: w *= sqrt(E_old / E_new) when E_new > E_old
    scale = np.sqrt(
        np.where(energy_new > energy_old, energy_old / np.maximum(energy_new, settings.TINY), 1.0)
    )
    bodies.body_rotation[index] = q_new
    bodies.body_angular_velocity[index] = w_new * scale[:, None]


def _normalize(q: np.ndarray) -> np.ndarray:
    """``q / |q|`` along the last axis."""
    return q / vector_length(q)
