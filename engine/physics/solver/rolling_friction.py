"""Rolling and spinning resistance at contacts (Bullet's rolling / spinning friction, which
Habitat exposes as ``rolling_friction_coefficient`` and ``spinning_friction_coefficient``).

A point contact cannot resist rolling (a ball rolls forever on a flat floor) nor spinning
about the normal; real contacts are patches that can. Bullet models both as limits on the
relative angular velocity ``w_rel = w_b - w_a`` of the two bodies of a manifold:

* spinning, about the contact normal ``n``: an angular impulse ``L_s n`` with
  ``L_s = -(w_rel . n) / K_s``, ``K_s = n . (I_a^-1 + I_b^-1) n``, clamped to
  ``|L_s| <= mu_spin lambda_n``;
* rolling, about the two tangents ``T = [t1 t2]``: ``L_r = -K_r^-1 T^T w_rel`` with
  ``K_r = T^T (I_a^-1 + I_b^-1) T`` (2x2), clamped to ``|L_r| <= mu_roll lambda_n``;

applied as ``w_a -= I_a^-1 L``, ``w_b += I_b^-1 L``. ``lambda_n`` is the normal impulse of the
manifold this step (N s), so the resisting torque is at most ``mu N`` (``mu`` in meters, a
lever arm). Pair coefficients combine as Bullet's ``btManifoldResult``:
``mu_roll = r_a f_b + r_b f_a`` (``r`` rolling, ``f`` Coulomb friction), clamped to
[0, 10]; the same for spinning. A ball of radius ``r`` rolling on a floor then decelerates at
``a = mu_roll g / (r (1 + I / (m r^2)))``, 5/7 ``mu_roll g / r`` for a solid sphere.

Differences from Bullet, on purpose: the limit uses the manifold's total normal impulse
(Bullet uses its first point's) and is not capped at ``mu`` itself (Bullet's unit-mixing cap
``min(mu lambda_n, mu)``). One pass per step, after the contact iterations: the contact
friction of the next step re-establishes rolling without slipping.

Two paths: :func:`rolling_friction_scalar` loops over manifolds;
:func:`rolling_friction_vectorized` solves one graph color per NumPy batch (manifolds of a
color share no dynamic body), in the same order, so both agree (tested).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..core.quaternions import cross
from ..core.settings import TANGENT_AXIS_SWITCH, TINY

__all__ = [
    "ContactLoads",
    "apply_rolling_friction",
    "combined_coefficients",
    "needs_rolling_friction",
]

#: Bullet's clamp of combined friction coefficients.
MAX_COMBINED = 10.0


def needs_rolling_friction(bodies, pair_bodies: np.ndarray) -> bool:
    """True when a body of the solved pairs ``pair_bodies (m, 2)`` has a non-zero rolling or
    spinning coefficient. Otherwise every pair coefficient is 0 and the solve stage skips
    rolling friction altogether (it builds no :class:`ContactLoads`): the common case costs
    nothing, and the result is the same (the resistance of a zero coefficient is 0)."""
    ids = pair_bodies.ravel()
    rolling = bodies.body_rolling_friction[ids] > 0.0
    spinning = bodies.body_spinning_friction[ids] > 0.0
    return bool(rolling.any() or spinning.any())


def combined_coefficients(
    bodies, body_a: np.ndarray, body_b: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """``(rolling, spinning)`` pair coefficients ``(m,)``: ``x_a f_b + x_b f_a``, in [0, 10]."""
    f_a, f_b = bodies.body_friction[body_a], bodies.body_friction[body_b]
    rolling = (
        bodies.body_rolling_friction[body_a] * f_b + bodies.body_rolling_friction[body_b] * f_a
    )
    spinning = (
        bodies.body_spinning_friction[body_a] * f_b + bodies.body_spinning_friction[body_b] * f_a
    )
    return np.clip(rolling, 0.0, MAX_COMBINED), np.clip(spinning, 0.0, MAX_COMBINED)


class ContactLoads(NamedTuple):
    """What rolling friction reads of the solved manifolds, in solver (color) order: the
    bodies ``body_a, body_b (m,)``, the graph colors ``color_slices``, each manifold's unit
    normal ``normal (m, 3)`` (from A to B) and its total normal impulse ``lambda_n (m,)``, N s.
    The batched solve builds it from its ``ContactBatch``, the reference from its rows."""

    body_a: np.ndarray
    body_b: np.ndarray
    color_slices: list[tuple[int, int]]
    normal: np.ndarray
    lambda_n: np.ndarray


def apply_rolling_friction(
    loads: ContactLoads,
    velocity: np.ndarray,
    inv_inertia: np.ndarray,
    rolling: np.ndarray,
    spinning: np.ndarray,
    vectorized: bool,
) -> None:
    """Change the angular velocities in ``velocity (n, 6)`` by the rolling and spinning
    impulses of every manifold of ``loads`` (a no-op when all coefficients are zero)."""
    if not (np.any(rolling > 0.0) or np.any(spinning > 0.0)):
        return
    if vectorized:
        rolling_friction_vectorized(
            loads, velocity, inv_inertia, loads.normal, loads.lambda_n, rolling, spinning
        )
    else:
        rolling_friction_scalar(
            loads, velocity, inv_inertia, loads.normal, loads.lambda_n, rolling, spinning
        )


def _tangents(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit tangents ``(..., 3)`` of unit normals (the least aligned axis trick)."""
    axis = np.zeros_like(normal)
    axis[..., 0] = np.abs(normal[..., 0]) < TANGENT_AXIS_SWITCH
    axis[..., 1] = 1.0 - axis[..., 0]
    t1 = cross(normal, axis)
    t1 /= np.linalg.norm(t1, axis=-1, keepdims=True)
    return t1, cross(normal, t1)


def rolling_friction_scalar(
    batch, velocity, inv_inertia, normal, lambda_n, rolling, spinning
) -> None:
    """Reference: one manifold at a time, in batch (color) order."""
    for m in range(len(batch.body_a)):
        if lambda_n[m] <= 0.0:
            continue
        a, b = int(batch.body_a[m]), int(batch.body_b[m])
        k_inv = inv_inertia[a] + inv_inertia[b]  # I_a^-1 + I_b^-1
        n = normal[m]
        if spinning[m] > 0.0:
            w_rel = velocity[b, 3:] - velocity[a, 3:]
            k_spin = float(n @ k_inv @ n)
            if k_spin > 0.0:
                limit = spinning[m] * lambda_n[m]
                impulse = float(np.clip(-(w_rel @ n) / k_spin, -limit, limit)) * n
                velocity[a, 3:] -= inv_inertia[a] @ impulse
                velocity[b, 3:] += inv_inertia[b] @ impulse
        if rolling[m] > 0.0:
            t1, t2 = _tangents(n)
            basis = np.stack([t1, t2], axis=1)  # (3, 2)
            w_rel = velocity[b, 3:] - velocity[a, 3:]
            k_roll = basis.T @ k_inv @ basis
            if abs(np.linalg.det(k_roll)) > TINY:
                amount = -np.linalg.solve(k_roll, basis.T @ w_rel)
                limit = rolling[m] * lambda_n[m]
                amount *= min(1.0, limit / max(float(np.linalg.norm(amount)), TINY))
                impulse = basis @ amount
                velocity[a, 3:] -= inv_inertia[a] @ impulse
                velocity[b, 3:] += inv_inertia[b] @ impulse


def rolling_friction_vectorized(
    batch, velocity, inv_inertia, normal, lambda_n, rolling, spinning
) -> None:
    """The same algebra, one NumPy batch per graph color."""
    t1, t2 = _tangents(normal)
    for start, stop in batch.color_slices:
        s = slice(start, stop)
        a, b = batch.body_a[s], batch.body_b[s]
        k_inv = inv_inertia[a] + inv_inertia[b]  # (k, 3, 3)
        n = normal[s]
        # spinning: L_s = clip(-(w_rel . n) / (n K n), +-mu_s lambda_n) n
        w_rel = velocity[b, 3:] - velocity[a, 3:]
        k_spin = np.einsum("ki,kij,kj->k", n, k_inv, n)
        limit = spinning[s] * np.maximum(lambda_n[s], 0.0)
        amount = np.where(k_spin > 0.0, -(w_rel * n).sum(1) / np.where(k_spin > 0, k_spin, 1), 0)
        impulse = np.clip(amount, -limit, limit)[:, None] * n
        _apply(velocity, inv_inertia, a, b, impulse)
        # rolling: L_r = -K_r^-1 T^T w_rel, clamped to the disc |L_r| <= mu_r lambda_n
        basis = np.stack([t1[s], t2[s]], axis=2)  # (k, 3, 2)
        w_rel = velocity[b, 3:] - velocity[a, 3:]
        k_roll = np.swapaxes(basis, 1, 2) @ k_inv @ basis  # (k, 2, 2)
        solvable = np.abs(np.linalg.det(k_roll)) > TINY
        rhs = (np.swapaxes(basis, 1, 2) @ w_rel[..., None])[..., 0]
        amount = np.zeros((len(a), 2))
        if solvable.any():
            amount[solvable] = -np.linalg.solve(k_roll[solvable], rhs[solvable][..., None])[..., 0]
        limit = rolling[s] * np.maximum(lambda_n[s], 0.0)
        norm = np.linalg.norm(amount, axis=1)
        amount *= np.minimum(1.0, limit / np.maximum(norm, TINY))[:, None]
        _apply(velocity, inv_inertia, a, b, (basis @ amount[..., None])[..., 0])


def _apply(velocity, inv_inertia, a, b, impulse) -> None:
    """Angular impulses ``(k, 3)``: ``w_a -= I_a^-1 L``, ``w_b += I_b^-1 L``."""
    velocity[a, 3:] -= (inv_inertia[a] @ impulse[..., None])[..., 0]
    velocity[b, 3:] += (inv_inertia[b] @ impulse[..., None])[..., 0]
