"""State arrays of every rigid body in the world (MuJoCo-style ``body_<quantity>`` arrays).

Body index ``i`` is the Habitat object id: index 0 is the stage, objects start at 1.
Arrays grow by doubling. A removed body's slot is cleared (``body_alive[i] = False``, every
array zeroed) and pushed on a free list; the next new body takes the most recently freed
slot, as Habitat's ``PhysicsManager::allocateObjectID`` pops its ``recycledObjectIDs_``
(a stack), so ``count`` and every per-step array stay as long as the most bodies ever
alive at once: adding and removing objects forever leaks nothing.

The arrays are declared below (``Bodies``), one annotated attribute each with its shape,
dtype, frame and units, as MuJoCo's ``mjData`` does; :data:`BODY_ARRAYS` lists them with
their per-body shape and dtype for allocation and growth. The table, for reading:

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
body_inertia               (n, 3)       diagonal inertia about the COM, body axes, kg m^2
body_motion_type           (n,)         int, a MotionType (STATIC 0, KINEMATIC 1, DYNAMIC 2)
body_friction              (n,)         Coulomb coefficient (pair value = product)
body_rolling_friction      (n,)         rolling resistance, m (pair: Bullet's r_a f_b + r_b f_a)
body_spinning_friction     (n,)         spinning resistance, m (same combination)
body_collision_group       (n,)         int, the body's CollisionGroups bit
body_collision_mask        (n,)         int, the groups it collides with (copied from its group)
body_restitution           (n,)         coefficient of restitution (pair value = product)
body_linear_damping        (n,)         1/s style fraction d, ``v *= (1 - d)^dt``
body_angular_damping       (n,)         same for angular velocity
body_awake                 (n,)         bool, sleeping bodies are skipped by the solver
body_sleep_time            (n,)         s the body has been resting
body_collidable            (n,)         bool
body_alive                 (n,)         bool
body_aabb_min/max          (n, 3)       world-frame AABB of all shapes, m
body_shape_center/half     (n, 3)       body-frame AABB (center, half size) of all shapes, m
body_solver_velocity       (n, 3)       linear velocity of a KINEMATIC body seen by contacts
body_solver_angular_vel.   (n, 3)       angular one (from its velocity control), rad/s
body_min_half_extent       (n,)         smallest half extent, m (CCD threshold)
=========================  ===========  ===========================================
"""

from __future__ import annotations

import numpy as np

from .motion_type import MotionType

#: The :class:`MotionType` values stored in ``body_motion_type``, as plain ints: NumPy
#: compares an array with an int directly, while an enum member costs it attribute lookups
#: on every comparison (measurable in the per-node loops of a step).
STATIC, KINEMATIC, DYNAMIC = (
    int(MotionType.STATIC),
    int(MotionType.KINEMATIC),
    int(MotionType.DYNAMIC),
)
#: body index (and Habitat object id) of the stage.
STAGE_ID = 0

#: every ``body_*`` array: per-body shape (after the body axis) and dtype.
BODY_ARRAYS: dict[str, tuple[tuple[int, ...], type]] = {
    "body_position": ((3,), np.float64),
    "body_rotation": ((4,), np.float64),
    "body_linear_velocity": ((3,), np.float64),
    "body_angular_velocity": ((3,), np.float64),
    "body_force": ((3,), np.float64),
    "body_torque": ((3,), np.float64),
    "body_mass": ((), np.float64),
    "body_inertia": ((3,), np.float64),
    "body_motion_type": ((), np.int64),
    "body_friction": ((), np.float64),
    "body_rolling_friction": ((), np.float64),
    "body_spinning_friction": ((), np.float64),
    "body_collision_group": ((), np.int64),
    "body_collision_mask": ((), np.int64),
    "body_restitution": ((), np.float64),
    "body_linear_damping": ((), np.float64),
    "body_angular_damping": ((), np.float64),
    "body_awake": ((), np.bool_),
    "body_sleep_time": ((), np.float64),
    "body_collidable": ((), np.bool_),
    "body_alive": ((), np.bool_),
    "body_aabb_min": ((3,), np.float64),
    "body_aabb_max": ((3,), np.float64),
    "body_shape_center": ((3,), np.float64),
    "body_shape_half": ((3,), np.float64),
    "body_solver_velocity": ((3,), np.float64),
    "body_solver_angular_velocity": ((3,), np.float64),
    "body_min_half_extent": ((), np.float64),
}


class Bodies:
    """Structure of arrays holding the state of all bodies (see the module docstring).

    Arrays hold ``capacity`` rows; rows ``[0, count)`` are in use.
    """

    body_position: np.ndarray  #: (n, 3) float, center of mass, world frame, m
    body_rotation: np.ndarray  #: (n, 4) float, world_from_body quaternion [x, y, z, w]
    body_linear_velocity: np.ndarray  #: (n, 3) float, world frame, m/s
    body_angular_velocity: np.ndarray  #: (n, 3) float, world frame, rad/s
    body_force: np.ndarray  #: (n, 3) float, world frame, N (cleared after step_physics)
    body_torque: np.ndarray  #: (n, 3) float, world frame, N m (cleared after step_physics)
    body_mass: np.ndarray  #: (n,) float, kg
    body_inertia: np.ndarray  #: (n, 3) float, diagonal inertia, body axes, kg m^2
    body_motion_type: np.ndarray  #: (n,) int, MotionType value
    body_friction: np.ndarray  #: (n,) float, Coulomb coefficient (pair: product)
    body_rolling_friction: np.ndarray  #: (n,) float, rolling resistance, m (see rolling_friction)
    body_spinning_friction: np.ndarray  #: (n,) float, spinning resistance, m (same combination)
    body_collision_group: np.ndarray  #: (n,) int, the body's CollisionGroups bit
    body_collision_mask: np.ndarray  #: (n,) int, the groups it collides with
    body_restitution: np.ndarray  #: (n,) float, restitution coefficient (pair: product)
    body_linear_damping: np.ndarray  #: (n,) float, fraction d: ``v *= (1 - d)^dt``
    body_angular_damping: np.ndarray  #: (n,) float, same for w
    body_awake: np.ndarray  #: (n,) bool, False: asleep (skipped by the solver)
    body_sleep_time: np.ndarray  #: (n,) float, s the body has been resting
    body_collidable: np.ndarray  #: (n,) bool
    body_alive: np.ndarray  #: (n,) bool, False for free slots
    body_aabb_min: np.ndarray  #: (n, 3) float, world AABB of all shapes, m
    body_aabb_max: np.ndarray  #: (n, 3) float
    body_shape_center: np.ndarray  #: (n, 3) float, body-frame AABB center of all shapes, m
    body_shape_half: np.ndarray  #: (n, 3) float, body-frame AABB half extents, m
    body_solver_velocity: np.ndarray  #: (n, 3) float, KINEMATIC velocity seen by contacts, m/s
    body_solver_angular_velocity: np.ndarray  #: (n, 3) float, same, rad/s
    body_min_half_extent: np.ndarray  #: (n,) float, smallest half extent, m (CCD-lite)

    def __init__(self, capacity: int = 16) -> None:
        self.count = 0
        for name, (shape, dtype) in BODY_ARRAYS.items():
            setattr(self, name, np.zeros((capacity, *shape), dtype=dtype))
        self.body_rotation[:, 3] = 1.0  # identity rotations
        self.shapes: list[list] = [[] for _ in range(capacity)]
        self.free_slots: list[int] = []  # freed object slots, most recently freed last

    @property
    def capacity(self) -> int:
        return len(self.body_mass)

    def arrays(self) -> dict[str, np.ndarray]:
        """``{name: array}`` of every ``body_*`` array, in :data:`BODY_ARRAYS` order."""
        return {name: getattr(self, name) for name in BODY_ARRAYS}

    def _grow(self) -> None:
        new = 2 * self.capacity
        for name, value in self.arrays().items():
            pad = np.zeros((new - len(value),) + value.shape[1:], dtype=value.dtype)
            setattr(self, name, np.concatenate([value, pad]))
        self.body_rotation[self.count :, 3] = 1.0
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
        for value in self.arrays().values():
            value[index] = 0
        self.body_rotation[index] = (0.0, 0.0, 0.0, 1.0)
        self.shapes[index] = []

    def state_bytes(self) -> bytes:
        """All body state as bytes, for hashing (determinism and unchanged-state tests)."""
        n = self.count
        parts = [getattr(self, name)[:n].tobytes() for name in sorted(BODY_ARRAYS)]
        return b"".join(parts)
