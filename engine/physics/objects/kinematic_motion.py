"""The velocity contacts see on a KINEMATIC body the user moves by setting its pose.

Habitat's kinematic objects have a Bullet motion state: each ``stepSimulation`` call
starts with ``btRigidBody::saveKinematicState(T)``, which reads the body's pose from its
scene node and sets its velocity from the pose it had at the previous call
(``btTransformUtil::calculateVelocity``)::

    v = (x_now - x_prev) / T,        w = axis(q_now q_prev^-1) angle(q_now q_prev^-1) / T

with ``T`` the time the call simulates (its whole fixed steps). A kinematic box moved by
``obj.translation`` every frame therefore pushes the bodies it meets along with it; with a
zero velocity only the position solve (capped at ``MAX_CORRECTION_SPEED``) would separate
them, and a body squeezed between the box and the floor was pushed into the floor.

:class:`KinematicPoses` remembers each kinematic body's pose after a call;
:func:`implied_velocities` writes ``body_solver_velocity`` / ``body_solver_angular_velocity``
of the bodies that moved since (velocity control sets its own, see ``world``). Speeds are
clamped to ``MAX_LINEAR_SPEED`` and ``MAX_ANGULAR_SPEED`` like every other velocity.
"""

from __future__ import annotations

import numpy as np

from ..core import settings
from ..core.bodies import KINEMATIC, Bodies
from ..core.quaternions import rotation_vector
from ..solver.integrate import clamp_rows


class KinematicPoses:
    """Pose ``(position (3,), rotation (4,))`` of every kinematic body after the last call
    that stepped (``poses``: body index -> pose)."""

    def __init__(self) -> None:
        self.poses: dict[int, tuple[np.ndarray, np.ndarray]] = {}

    def record(self, bodies: Bodies) -> None:
        """Remember the poses of the live kinematic bodies (and forget every other body)."""
        n = bodies.count
        kinematic = np.flatnonzero(
            bodies.body_alive[:n] & (bodies.body_motion_type[:n] == KINEMATIC)
        )
        self.poses = {
            int(i): (bodies.body_position[i].copy(), bodies.body_rotation[i].copy())
            for i in kinematic.tolist()
        }

    def clear(self) -> None:
        self.poses = {}


def implied_velocities(
    bodies: Bodies, poses: KinematicPoses, controlled: set[int], duration: float
) -> None:
    """Set the solver velocities of the kinematic bodies that moved since ``poses`` was
    recorded, over ``duration`` seconds (> 0); bodies in ``controlled`` (an active velocity
    control) keep theirs."""
    moved = [
        i
        for i, (position, rotation) in poses.poses.items()
        if i not in controlled
        and bodies.body_alive[i]
        and bodies.body_motion_type[i] == KINEMATIC
        and not (
            np.array_equal(bodies.body_position[i], position)
            and np.array_equal(bodies.body_rotation[i], rotation)
        )
    ]
    if not moved:
        return
    index = np.array(moved)
    before = np.array([poses.poses[i][0] for i in moved])
    turned = np.array([poses.poses[i][1] for i in moved])
    linear = (bodies.body_position[index] - before) / duration
    angular = rotation_vector(bodies.body_rotation[index], turned) / duration
    bodies.body_solver_velocity[index] = clamp_rows(linear, settings.MAX_LINEAR_SPEED)
    bodies.body_solver_angular_velocity[index] = clamp_rows(angular, settings.MAX_ANGULAR_SPEED)
