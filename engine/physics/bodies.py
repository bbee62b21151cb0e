"""State arrays of every rigid body in the world (MuJoCo-style ``body_<quantity>`` arrays).

Body index ``i`` is the Habitat object id: index 0 is the stage, objects start at 1.
Arrays grow by doubling. A removed body's slot is cleared (``body_alive[i] = False``, every
array zeroed) and pushed on a free list; the next new body takes the most recently freed
slot, as Habitat's ``PhysicsManager::allocateObjectID`` pops its ``recycledObjectIDs_``
(a stack), so ``count`` and every per-step array stay as long as the most bodies ever
alive at once: adding and removing objects forever leaks nothing.

=========================  ===========  ===========================================
array                      shape        meaning (frame, units)
=========================  ===========  ===========================================
body_position              (n, 3)       center of mass, world frame, m
body_rotation              (n, 4)       world_from_body quaternion [x, y, z, w]
body_linear_velocity       (n, 3)       world frame, m/s
body_angular_velocity      (n, 3)       world frame, rad/s
body_force                 (n, 3)       world frame, N, cleared after each step_physics
body_torque                (n, 3)       world frame, N m, cleared after each step_physics
body_mass                  (n,)         kg
body_inv_mass              (n,)         1/kg, 0 for static/kinematic/sleeping bodies
body_inertia               (n, 3)       diagonal inertia about the COM, body axes, kg m^2
body_motion_type           (n,)         MotionType value (0 static, 1 kinematic, 2 dynamic)
body_friction              (n,)         Coulomb coefficient (pair value = product)
body_restitution           (n,)         coefficient of restitution (pair value = product)
body_linear_damping        (n,)         1/s style fraction d, v *= (1 - d)^dt
body_angular_damping       (n,)         same for angular velocity
body_awake                 (n,)         bool, sleeping bodies are skipped by the solver
body_sleep_time            (n,)         s the body has been resting
body_collidable            (n,)         bool
body_alive                 (n,)         bool
body_aabb_min/max          (n, 3)       world-frame AABB of all shapes, m
body_shape_center/half     (n, 3)       body-frame AABB (center, half size) of all shapes, m
body_solver_velocity       (n, 3)       linear velocity of a KINEMATIC body seen by contacts
body_solver_angular_vel.   (n, 3)       angular one (from its velocity control), rad/s
body_min_half_extent       (n,)         smallest half extent, m (CCD-lite threshold)
=========================  ===========  ===========================================
"""

from __future__ import annotations

import numpy as np

STATIC, KINEMATIC, DYNAMIC = 0, 1, 2
#: body index (and Habitat object id) of the stage.
STAGE_ID = 0

_VECTORS = ("position", "linear_velocity", "angular_velocity", "force", "torque",
            "inertia", "aabb_min", "aabb_max", "shape_center", "shape_half", "solver_velocity",
            "solver_angular_velocity")
_SCALARS = ("mass", "friction", "restitution", "linear_damping", "angular_damping",
            "sleep_time", "min_half_extent")
_FLAGS = ("awake", "collidable", "alive")


class Bodies:
    """Structure of arrays holding the state of all bodies (see module docstring)."""

    def __init__(self, capacity: int = 16) -> None:
        self.count = 0
        for name in _VECTORS:
            setattr(self, "body_" + name, np.zeros((capacity, 3)))
        for name in _SCALARS:
            setattr(self, "body_" + name, np.zeros(capacity))
        for name in _FLAGS:
            setattr(self, "body_" + name, np.zeros(capacity, dtype=bool))
        self.body_rotation = np.tile([0.0, 0.0, 0.0, 1.0], (capacity, 1))
        self.body_motion_type = np.zeros(capacity, dtype=np.int64)
        self.shapes: list[list] = [[] for _ in range(capacity)]
        self.free_slots: list[int] = []  # freed object slots, most recently freed last

    @property
    def capacity(self) -> int:
        return len(self.body_mass)

    def _grow(self) -> None:
        new = 2 * self.capacity
        for name, value in list(vars(self).items()):
            if name.startswith("body_"):
                pad = np.zeros((new - len(value),) + value.shape[1:], dtype=value.dtype)
                setattr(self, name, np.concatenate([value, pad]))
        self.body_rotation[self.count:, 3] = 1.0
        self.shapes += [[] for _ in range(new - len(self.shapes))]

    def add(self, index: int) -> None:
        """Reserve slot ``index`` (must be the next free one or a stage slot 0)."""
        while index >= self.capacity:
            self._grow()
        self.count = max(self.count, index + 1)
        self._clear(index)
        self.body_alive[index] = True
        self.body_awake[index] = True
        self.body_collidable[index] = True
        self.body_rotation[index] = (0.0, 0.0, 0.0, 1.0)

    def next_slot(self) -> int:
        """The slot a new body gets: the most recently freed one, else a new one at the end."""
        return self.free_slots[-1] if self.free_slots else self.count

    def allocate(self) -> int:
        """Reserve and return :meth:`next_slot` (cleared, alive, awake, collidable)."""
        index = self.next_slot()
        if self.free_slots:
            self.free_slots.pop()
        self.add(index)
        return index

    def release(self, index: int) -> None:
        """Free slot ``index``: clear its state (``body_alive`` False) and recycle it."""
        self._clear(index)
        if index != 0 and index not in self.free_slots:
            self.free_slots.append(index)

    def _clear(self, index: int) -> None:
        """Zero every ``body_*`` array at ``index`` (identity rotation, no shapes)."""
        for name, value in vars(self).items():
            if name.startswith("body_"):
                value[index] = 0
        self.body_rotation[index] = (0.0, 0.0, 0.0, 1.0)
        self.shapes[index] = []

    @property
    def body_inv_mass(self) -> np.ndarray:
        """(n,) 1/kg for awake dynamic bodies, 0 for everything that does not move by forces."""
        n = self.count
        moving = (self.body_motion_type[:n] == DYNAMIC) & self.body_awake[:n] & self.body_alive[:n]
        return np.where(moving, 1.0 / np.maximum(self.body_mass[:n], 1e-300), 0.0)

    def state_bytes(self) -> bytes:
        """All body state as bytes, for hashing (determinism and unchanged-state tests)."""
        n = self.count
        parts = [getattr(self, name)[:n].tobytes() for name in sorted(vars(self))
                 if name.startswith("body_")]
        return b"".join(parts)
