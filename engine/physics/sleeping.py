"""Sleeping and waking by islands (Box2D / Bullet style).

A dynamic body is *resting* while ``|v| < SLEEP_LINEAR_VELOCITY`` and
``|w| < SLEEP_ANGULAR_VELOCITY``; its ``body_sleep_time`` counts how long. Bodies joined by
contact manifolds form islands (connected components of the contact graph between dynamic
bodies; static and kinematic bodies do not join islands). An island falls asleep when its
least-rested body has rested ``TIME_TO_SLEEP`` seconds: velocities are zeroed and the solver
treats its bodies as static until woken. A sleeping body in an island that also holds an
awake, non-resting body is woken, so a moving body wakes whatever it touches; touching a
moving kinematic body resets the rest timer.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from . import settings
from .bodies import DYNAMIC, KINEMATIC


def update_sleep(bodies, manifolds, h: float) -> None:
    """Advance rest timers, then put resting islands to sleep and wake disturbed ones."""
    n = bodies.count
    dynamic = bodies.body_alive[:n] & (bodies.body_motion_type[:n] == DYNAMIC)
    awake = dynamic & bodies.body_awake[:n]
    speed_sq = np.sum(bodies.body_linear_velocity[:n] ** 2, axis=1)
    spin_sq = np.sum(bodies.body_angular_velocity[:n] ** 2, axis=1)
    slow = (speed_sq < settings.SLEEP_LINEAR_VELOCITY**2) & (
        spin_sq < settings.SLEEP_ANGULAR_VELOCITY**2)
    time = bodies.body_sleep_time[:n]
    time[awake & slow] += h
    time[awake & ~slow] = 0.0
    edges = []
    is_dynamic, pushing = dynamic.tolist(), None
    for (a, b), manifold in manifolds.items():
        if len(manifold) == 0:
            continue
        if is_dynamic[a] and is_dynamic[b]:
            edges.append((a, b))
            continue
        if pushing is None:  # built on first need: most steps have no kinematic contact
            pushing = _moving_kinematic_mask(bodies, n).tolist()
        if pushing[a] or pushing[b]:
            time[a if is_dynamic[a] else b] = 0.0
    labels = _island_labels(n, edges)
    island_rest = np.full(n, np.inf)
    np.minimum.at(island_rest, labels[dynamic], time[dynamic])
    asleep = dynamic & (island_rest[labels] >= settings.TIME_TO_SLEEP)
    falling_asleep = asleep & bodies.body_awake[:n]
    bodies.body_linear_velocity[:n][falling_asleep] = 0.0
    bodies.body_angular_velocity[:n][falling_asleep] = 0.0
    woken = dynamic & ~asleep & ~bodies.body_awake[:n]
    time[woken] = 0.0
    bodies.body_awake[:n] = np.where(dynamic, ~asleep, bodies.body_awake[:n])


def _moving_kinematic_mask(bodies, n: int) -> np.ndarray:
    """(n,) bool: KINEMATIC bodies with a non-zero velocity-control velocity."""
    moving = (bodies.body_solver_velocity[:n] != 0).any(1) | (
        bodies.body_solver_angular_velocity[:n] != 0).any(1)
    return (bodies.body_motion_type[:n] == KINEMATIC) & moving


def _island_labels(n: int, edges: list) -> np.ndarray:
    """Connected-component label ``(n,)`` of every body in the contact graph."""
    if not edges:
        return np.arange(n)
    pairs = np.array(edges, dtype=np.int64)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    return connected_components(graph, directed=False)[1]


def wake_touched(bodies, manifolds) -> bool:
    """Wake sleeping dynamic bodies touching an awake dynamic or a moving kinematic body.

    Runs right after collision detection, so the solver already treats a body that was hit
    this step as movable (otherwise it would act as a wall for one step). Returns True when a
    body was woken.
    """
    woken = False
    awake = bodies.body_awake
    n = bodies.count
    is_dynamic = (bodies.body_motion_type[:n] == DYNAMIC).tolist()
    pushing = None
    for (a, b), manifold in manifolds.items():
        if len(manifold) == 0:
            continue
        for sleeper, other in ((a, b), (b, a)):
            if not is_dynamic[sleeper] or awake[sleeper]:
                continue
            if pushing is None:  # built on first need (a sleeper touches something)
                pushing = _moving_kinematic_mask(bodies, n).tolist()
            if (is_dynamic[other] and awake[other]) or pushing[other]:
                awake[sleeper] = True
                bodies.body_sleep_time[sleeper] = 0.0
                woken = True
    return woken
