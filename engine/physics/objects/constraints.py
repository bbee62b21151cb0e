"""Rigid constraints between two bodies, or a body and the world (Habitat's
``RigidConstraintSettings``, ``RigidConstraintType``, ``sim.create_rigid_constraint``).

Two kinds, as Habitat's Bullet backend offers them:

* ``PointToPoint`` (a ball joint): the world points ``p_a = x_a + R_a pivot_a`` and
  ``p_b = x_b + R_b pivot_b`` coincide (``pivot_b`` is a world point when ``object_id_b`` is
  -1, the world);
* ``Fixed`` (a weld): the same point condition plus equal orientations of the two constraint
  frames, ``R_a frame_a = R_b frame_b``.

Solver (Catto, "Iterative Dynamics with Temporal Coherence", GDC 2005; Bullet's
``btPoint2PointConstraint``): sequential impulses at the velocity level with Baumgarte
stabilization. With anchors ``r_k = R_k pivot_k`` and the point error ``C = p_b - p_a``,
the relative anchor velocity ``v_rel = (v_b + w_b x r_b) - (v_a + w_a x r_a)`` is driven to
``-beta C / h``. One 3x3 block per constraint::

    K = (1/m_a + 1/m_b) I - [r_a]x I_a^-1 [r_a]x - [r_b]x I_b^-1 [r_b]x
    lambda = -K^-1 (v_rel + beta C / h)                       (an impulse, N s)
    v_a -= lambda / m_a,  w_a -= I_a^-1 (r_a x lambda),  v_b += ...,  w_b += I_b^-1 (r_b x lambda)

The angular block of a ``Fixed`` constraint drives ``w_b - w_a`` to ``-beta e / h`` with
``e = vee(R_err - R_err^T) / 2 = sin(theta) u`` for the rotation ``R_err = F_b F_a^T`` from
frame A to frame B (``F_k = R_k frame_k``; ``e ~ theta u`` for small errors) and
``K_ang = I_a^-1 + I_b^-1``. The accumulated impulse of each block is
clamped per row to ``max_impulse`` per step for ``PointToPoint`` (a weak constraint lets
go, as Bullet's ``m_impulseClamp``; ``Fixed`` ones are not clamped, as Habitat's). The bias
also carries the second-order drift of the rotating anchors (:func:`point_bias`). Static and
kinematic bodies have infinite mass; kinematic ones move with their velocity control.

Two paths, one algebra: :func:`solve_constraints_scalar` visits the constraints one by one;
:func:`solve_constraints_vectorized` solves all constraints of one graph color (no shared
dynamic body) as one NumPy batch. Colors are visited in order, so both are Gauss-Seidel
across colors and give the same numbers (tested). The constraint stage runs after the
contact solve of each step (a teaching simplification: contacts and constraints are not
interleaved within the iterations). Bodies held by a constraint do not fall asleep. A
constraint none of whose bodies is an awake DYNAMIC one (its object made KINEMATIC, two
STATIC objects) is inert: the step leaves it out (:meth:`ConstraintStore.active_ids`).
The settings and their checks are in :mod:`.constraint_settings`.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from ..core.bodies import Bodies
from ..core.quaternions import cross, quat_to_matrix
from ..core.settings import CONSTRAINT_BAUMGARTE, TINY, SolverSettings
from ..pipeline.solve_stage import solver_velocities
from ..solver.coloring import color_manifolds
from ..solver.integrate import world_inverse_inertia
from ..solver.sleeping import wake_body
from .constraint_settings import WORLD, RigidConstraintSettings, RigidConstraintType
from .world_view import WorldView

__all__ = ["ConstraintStore", "RigidConstraintSettings", "RigidConstraintType"]


@dataclass
class ConstraintRows:
    """Per-step arrays of ``k`` constraints (a ``b`` index of -1 is the world).

    ``r_a, r_b (k, 3)`` world anchors; ``error (k, 3)`` point error ``p_b - p_a``;
    ``k_inv (k, 3, 3)`` inverse linear effective mass; ``fixed (k,)`` bool;
    ``angle_error (k, 3)``; ``k_ang_inv (k, 3, 3)``; ``limit (k,)`` max impulse;
    ``lin_impulse, ang_impulse (k, 3)`` accumulated this step; ``colors``: index arrays of
    the graph colors, filled when the rows are sorted (:func:`order_by_color`; empty
    before); ``bias (k, 3)`` the velocity the point block aims at, negated, filled by
    :func:`point_bias` (``(0, 3)`` before).
    """

    a: np.ndarray
    b: np.ndarray
    r_a: np.ndarray
    r_b: np.ndarray
    error: np.ndarray
    k_inv: np.ndarray
    fixed: np.ndarray
    angle_error: np.ndarray
    k_ang_inv: np.ndarray
    limit: np.ndarray
    lin_impulse: np.ndarray
    ang_impulse: np.ndarray
    colors: list[np.ndarray] = field(default_factory=list)
    bias: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))


def _skew(v: np.ndarray) -> np.ndarray:
    """``(k, 3, 3)`` cross-product matrices ``[v]x`` with ``[v]x u = v x u``."""
    s = np.zeros(v.shape[:-1] + (3, 3))
    s[..., 0, 1], s[..., 0, 2] = -v[..., 2], v[..., 1]
    s[..., 1, 0], s[..., 1, 2] = v[..., 2], -v[..., 0]
    s[..., 2, 0], s[..., 2, 1] = -v[..., 1], v[..., 0]
    return s


class ConstraintStore:
    """The constraints of a world by id, and the per-step solve (see the module docstring)."""

    def __init__(self) -> None:
        self._settings: dict[int, RigidConstraintSettings] = {}
        self._next_id = 0

    def __len__(self) -> int:
        """The number of constraints."""
        return len(self._settings)

    # -- API ---------------------------------------------------------------------------------
    def create(self, world: WorldView, settings: RigidConstraintSettings) -> int:
        """A new constraint's id, or -1 with a warning when its bodies are not live objects
        (Habitat's failure value)."""
        if not isinstance(settings, RigidConstraintSettings):
            raise TypeError(f"expected RigidConstraintSettings, got {type(settings).__name__}")
        try:
            self._check_bodies(world, settings)
        except ValueError as error:
            warnings.warn(f"rigid constraint not created: {error}", stacklevel=3)
            return -1
        constraint_id = self._next_id
        self._next_id += 1
        self._settings[constraint_id] = settings.copy()
        self.wake_bodies(world.bodies)
        return constraint_id

    def update(
        self, world: WorldView, constraint_id: int, settings: RigidConstraintSettings
    ) -> None:
        self._get(constraint_id)
        self._check_bodies(world, settings)
        self._settings[constraint_id] = settings.copy()
        self.wake_bodies(world.bodies)

    def remove(self, world: WorldView, constraint_id: int) -> None:
        settings = self._get(constraint_id)
        del self._settings[constraint_id]
        for index in (settings.object_id_a, settings.object_id_b):
            if index != WORLD and index < world.bodies.count:
                wake_body(world.bodies, index)

    def get_settings(self, constraint_id: int) -> RigidConstraintSettings:
        return self._get(constraint_id).copy()

    def ids(self) -> list[int]:
        return sorted(self._settings)

    def _get(self, constraint_id: int) -> RigidConstraintSettings:
        if constraint_id not in self._settings:
            raise KeyError(f"no rigid constraint with id {constraint_id!r}")
        return self._settings[constraint_id]

    @staticmethod
    def _check_bodies(world: WorldView, settings: RigidConstraintSettings) -> None:
        b = world.bodies
        for name in ("object_id_a", "object_id_b"):
            index = getattr(settings, name)
            if name == "object_id_b" and index == WORLD:
                continue
            if not (1 <= index < b.count and b.body_alive[index]):
                raise ValueError(f"{name}={index} is not a live rigid object")
        if settings.object_id_a == settings.object_id_b:
            raise ValueError("a constraint needs two different bodies (or object_id_b = -1)")

    def drop_body(self, index: int) -> None:
        """Remove the constraints of a removed body."""
        for constraint_id in [
            c for c, s in self._settings.items() if index in (s.object_id_a, s.object_id_b)
        ]:
            del self._settings[constraint_id]

    # -- step hooks ------------------------------------------------------------------------------
    def wake_bodies(self, bodies: Bodies) -> None:
        """Bodies held by a constraint stay awake (a moving partner must be able to pull):
        wakes them in ``bodies`` (the first thing a step does)."""
        for settings in self._settings.values():
            for index in (settings.object_id_a, settings.object_id_b):
                if index != WORLD:
                    wake_body(bodies, index)

    def solve(self, bodies: Bodies, moving: np.ndarray, h: float, settings: SolverSettings) -> None:
        """Constraint stage of a step: build rows, iterate, write the dynamic velocities.

        Like the other stages, a function of explicit arrays and settings (no ``world``)."""
        active = self.active_ids(moving)
        if not active:  # no constraint has a body that can move: all are inert this step
            return
        velocity, inv_mass, inv_inertia = _body_state(bodies, bodies.count, moving)
        rows = self.build_rows(bodies, inv_mass, inv_inertia, h, active)
        rows = order_by_color(rows, inv_mass)
        rows.bias = point_bias(rows, velocity, h)
        iterations = settings.constraint_iterations
        if settings.use_vectorized:
            solve_constraints_vectorized(rows, velocity, inv_mass, inv_inertia, h, iterations)
        else:
            solve_constraints_scalar(rows, velocity, inv_mass, inv_inertia, h, iterations)
        bodies.body_linear_velocity[moving] = velocity[moving, :3]
        bodies.body_angular_velocity[moving] = velocity[moving, 3:]

    def active_ids(self, moving: np.ndarray) -> list[int]:
        """Ids of the constraints with at least one body among ``moving`` (awake DYNAMIC
        body indices). The others hold only static, kinematic or sleeping bodies: no
        impulse can move them, so they are inert this step (a constraint pinning an object
        made KINEMATIC, or two STATIC objects)."""
        movable = set(np.asarray(moving).tolist())
        return [
            c
            for c in self.ids()
            if movable & {self._settings[c].object_id_a, self._settings[c].object_id_b}
        ]

    def build_rows(
        self,
        b,
        inv_mass: np.ndarray,
        inv_inertia: np.ndarray,
        h: float,
        ids: list[int] | None = None,
    ) -> ConstraintRows:
        """Anchors, errors and effective masses of the constraints ``ids`` (default: every
        constraint) for this step."""
        settings = [self._settings[c] for c in (self.ids() if ids is None else ids)]
        k = len(settings)
        a = np.array([s.object_id_a for s in settings], dtype=np.int64)
        bb = np.array([s.object_id_b for s in settings], dtype=np.int64)
        world_b = bb == WORLD
        safe_b = np.where(world_b, 0, bb)
        rot_a = quat_to_matrix(b.body_rotation[a])
        rot_b = np.where(world_b[:, None, None], np.eye(3), quat_to_matrix(b.body_rotation[safe_b]))
        pos_b = np.where(world_b[:, None], 0.0, b.body_position[safe_b])
        pivot_a = np.array([np.asarray(s.pivot_a) for s in settings]).reshape(k, 3)
        pivot_b = np.array([np.asarray(s.pivot_b) for s in settings]).reshape(k, 3)
        r_a = (rot_a @ pivot_a[:, :, None])[..., 0]  # r = R pivot
        r_b = (rot_b @ pivot_b[:, :, None])[..., 0]
        error = (pos_b + r_b) - (b.body_position[a] + r_a)  # C = p_b - p_a
        inv_i_a = inv_inertia[a]
        inv_i_b = np.where(world_b[:, None, None], 0.0, inv_inertia[safe_b])
        inv_m = inv_mass[a] + np.where(world_b, 0.0, inv_mass[safe_b])
        skew_a, skew_b = _skew(r_a), _skew(r_b)
        # K = (1/m_a + 1/m_b) I - [r_a] I_a^-1 [r_a] - [r_b] I_b^-1 [r_b]
        k_lin = (
            inv_m[:, None, None] * np.eye(3) - skew_a @ inv_i_a @ skew_a - skew_b @ inv_i_b @ skew_b
        )
        fixed = np.array([s.constraint_type == RigidConstraintType.Fixed for s in settings])
        frame_a = np.array([np.asarray(s.frame_a) for s in settings]).reshape(k, 3, 3)
        frame_b = np.array([np.asarray(s.frame_b) for s in settings]).reshape(k, 3, 3)
        # R_err = F_b F_a^T takes frame A to frame B; e = vee(R_err - R_err^T) / 2
        r_err = (rot_b @ frame_b) @ np.swapaxes(rot_a @ frame_a, 1, 2)
        angle_error = 0.5 * np.stack(
            [
                r_err[:, 2, 1] - r_err[:, 1, 2],
                r_err[:, 0, 2] - r_err[:, 2, 0],
                r_err[:, 1, 0] - r_err[:, 0, 1],
            ],
            axis=1,
        )
        k_ang = inv_i_a + inv_i_b
        return ConstraintRows(
            a,
            bb,
            r_a,
            r_b,
            error,
            _safe_inverse(k_lin),
            fixed,
            angle_error,
            _safe_inverse(k_ang),
            # Bullet clamps a point-to-point constraint's rows, a fixed one not at all
            np.where(fixed, np.inf, np.array([s.max_impulse for s in settings])),
            np.zeros((k, 3)),
            np.zeros((k, 3)),
        )


def order_by_color(rows: ConstraintRows, inv_mass: np.ndarray) -> ConstraintRows:
    """Rows sorted by graph color (no two constraints of a color share a dynamic body), with
    ``rows.colors`` the index arrays of each color: the scalar loop then visits constraints
    in the very order the vectorized path solves them."""
    n = len(inv_mass)
    movable = np.append(inv_mass > 0.0, False)  # the world (index n) never moves
    colors = color_manifolds(rows.a, np.where(rows.b == WORLD, n, rows.b), movable)
    order = np.concatenate(colors)
    fields = {
        name: getattr(rows, name)[order]
        for name in ConstraintRows.__dataclass_fields__
        if name not in ("colors", "bias")
    }
    sizes = np.cumsum([0] + [len(c) for c in colors])
    return ConstraintRows(
        **fields, colors=[np.arange(lo, hi) for lo, hi in zip(sizes[:-1], sizes[1:], strict=True)]
    )


def _safe_inverse(matrices: np.ndarray) -> np.ndarray:
    """Inverse of each 3x3 matrix; zero for singular ones (two immovable bodies)."""
    out = np.zeros_like(matrices)
    regular = np.abs(np.linalg.det(matrices)) > TINY
    out[regular] = np.linalg.inv(matrices[regular])
    return out


def _body_state(b, n: int, moving: np.ndarray):
    """``(n, 6)`` velocities (kinematic: their controlled ones), inverse masses and world
    inverse inertias (zero for everything that is not an awake dynamic body)."""
    velocity = solver_velocities(b, n)
    inv_mass = np.zeros(n)
    inv_mass[moving] = 1.0 / b.body_mass[moving]
    inv_inertia = np.zeros((n, 3, 3))
    inv_inertia[moving] = world_inverse_inertia(b.body_rotation[moving], b.body_inertia[moving])
    return velocity, inv_mass, inv_inertia


def _clamp(accumulated: np.ndarray, step: np.ndarray, limit: np.ndarray) -> np.ndarray:
    """The step keeping every row of ``accumulated + step`` in ``[-limit, limit]``
    (``(k, 3)`` rows; Bullet's per-row impulse clamp)."""
    return np.clip(accumulated + step, -limit[:, None], limit[:, None]) - accumulated


def point_bias(rows: ConstraintRows, velocity: np.ndarray, h: float) -> np.ndarray:
    """``(k, 3)`` bias of the point blocks: Baumgarte ``beta C / h`` plus the drift the
    rotation integration will add to the anchors, ``(h / 2) [w_b x (w_b x r_b) -
    w_a x (w_a x r_a)]`` (an anchor turning at ``w`` moves along an arc, not along its
    tangent ``w x r``; this second-order term would otherwise accumulate as error)."""
    n = len(velocity)
    w_a = velocity[rows.a, 3:]
    w_b = np.where((rows.b == WORLD)[:, None], 0.0, velocity[np.minimum(rows.b, n - 1), 3:])
    curve = cross(w_b, cross(w_b, rows.r_b)) - cross(w_a, cross(w_a, rows.r_a))
    return CONSTRAINT_BAUMGARTE * rows.error / h + 0.5 * h * curve


# -- scalar reference path ---------------------------------------------------------------------
def solve_constraints_scalar(
    rows: ConstraintRows,
    velocity: np.ndarray,
    inv_mass: np.ndarray,
    inv_inertia: np.ndarray,
    h: float,
    iterations: int,
) -> None:
    """Reference: every constraint in turn, ``iterations`` times (module docstring)."""
    beta = CONSTRAINT_BAUMGARTE
    for _ in range(iterations):
        for i in range(len(rows.a)):
            a, b = int(rows.a[i]), int(rows.b[i])
            va, wa = velocity[a, :3], velocity[a, 3:]
            vb = velocity[b, :3] if b != WORLD else np.zeros(3)
            wb = velocity[b, 3:] if b != WORLD else np.zeros(3)
            # linear block: v_rel = (v_b + w_b x r_b) - (v_a + w_a x r_a)
            v_rel = vb + np.cross(wb, rows.r_b[i]) - va - np.cross(wa, rows.r_a[i])
            step = -rows.k_inv[i] @ (v_rel + rows.bias[i])
            step = _clamp(rows.lin_impulse[i : i + 1], step[None], rows.limit[i : i + 1])[0]
            rows.lin_impulse[i] += step
            _apply(velocity, inv_mass, inv_inertia, a, b, step, rows.r_a[i], rows.r_b[i])
            if not rows.fixed[i]:
                continue
            wa = velocity[a, 3:]
            wb = velocity[b, 3:] if b != WORLD else np.zeros(3)
            step = -rows.k_ang_inv[i] @ (wb - wa + beta * rows.angle_error[i] / h)
            step = _clamp(rows.ang_impulse[i : i + 1], step[None], rows.limit[i : i + 1])[0]
            rows.ang_impulse[i] += step
            velocity[a, 3:] -= inv_inertia[a] @ step
            if b != WORLD:
                velocity[b, 3:] += inv_inertia[b] @ step


def _apply(velocity, inv_mass, inv_inertia, a, b, impulse, r_a, r_b) -> None:
    """A linear impulse at the anchors: ``-lambda`` on A, ``+lambda`` on B."""
    velocity[a, :3] -= inv_mass[a] * impulse
    velocity[a, 3:] -= inv_inertia[a] @ np.cross(r_a, impulse)
    if b != WORLD:
        velocity[b, :3] += inv_mass[b] * impulse
        velocity[b, 3:] += inv_inertia[b] @ np.cross(r_b, impulse)


# -- vectorized path -----------------------------------------------------------------------------
def solve_constraints_vectorized(
    rows: ConstraintRows,
    velocity: np.ndarray,
    inv_mass: np.ndarray,
    inv_inertia: np.ndarray,
    h: float,
    iterations: int,
) -> None:
    """The same algebra as :func:`solve_constraints_scalar`, one NumPy batch per graph
    color (constraints of one color share no dynamic body, so the order inside a color does
    not matter)."""
    beta = CONSTRAINT_BAUMGARTE
    n = len(velocity)
    # the world is a virtual last body with zero velocity and zero inverse mass
    velocity_ext = np.vstack([velocity, np.zeros((1, 6))])
    inv_mass_ext = np.append(inv_mass, 0.0)
    inv_inertia_ext = np.concatenate([inv_inertia, np.zeros((1, 3, 3))])
    b_index = np.where(rows.b == WORLD, n, rows.b)
    for _ in range(iterations):
        for color in rows.colors:
            a, b = rows.a[color], b_index[color]
            r_a, r_b = rows.r_a[color], rows.r_b[color]
            va, wa = velocity_ext[a, :3], velocity_ext[a, 3:]
            vb, wb = velocity_ext[b, :3], velocity_ext[b, 3:]
            v_rel = vb + cross(wb, r_b) - va - cross(wa, r_a)
            # lambda = -K^-1 (v_rel + beta C / h) for the whole color at once
            step = -(rows.k_inv[color] @ (v_rel + rows.bias[color])[..., None])[..., 0]
            step = _clamp(rows.lin_impulse[color], step, rows.limit[color])
            rows.lin_impulse[color] += step
            inv_i_a, inv_i_b = inv_inertia_ext[a], inv_inertia_ext[b]
            velocity_ext[a, :3] -= inv_mass_ext[a][:, None] * step
            velocity_ext[a, 3:] -= (inv_i_a @ cross(r_a, step)[..., None])[..., 0]
            velocity_ext[b, :3] += inv_mass_ext[b][:, None] * step
            velocity_ext[b, 3:] += (inv_i_b @ cross(r_b, step)[..., None])[..., 0]
            fixed = color[rows.fixed[color]]
            if len(fixed) == 0:
                continue
            a, b = rows.a[fixed], b_index[fixed]
            w_rel = velocity_ext[b, 3:] - velocity_ext[a, 3:]
            step = -(
                rows.k_ang_inv[fixed] @ (w_rel + beta * rows.angle_error[fixed] / h)[..., None]
            )[..., 0]
            step = _clamp(rows.ang_impulse[fixed], step, rows.limit[fixed])
            rows.ang_impulse[fixed] += step
            velocity_ext[a, 3:] -= (inv_inertia_ext[a] @ step[..., None])[..., 0]
            velocity_ext[b, 3:] += (inv_inertia_ext[b] @ step[..., None])[..., 0]
        velocity_ext[n] = 0.0  # the world never moves
    velocity[...] = velocity_ext[:n]
