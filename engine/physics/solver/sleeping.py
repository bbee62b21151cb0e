"""Sleeping and waking by islands (Box2D / Bullet style).

A dynamic body is *resting* while ``|v| < SLEEP_LINEAR_VELOCITY`` and
``|w| < SLEEP_ANGULAR_VELOCITY``; its ``body_sleep_time`` counts how long. Bodies joined by
contact manifolds form islands (connected components of the contact graph between dynamic
bodies; static and kinematic bodies do not join islands). An island falls asleep when its
least-rested body has rested ``TIME_TO_SLEEP`` seconds (a body still overlapping another by
more than ``SLEEP_MAX_PENETRATION`` is not resting): velocities are zeroed and the solver
treats its bodies as static until woken. A sleeping body in an island that also holds an
awake, non-resting body is woken, so a moving body wakes whatever it touches; touching a
moving kinematic body resets the rest timer. Outside the step, :func:`wake_body` and
:func:`wake_island` wake what a user's change (a pose write, a removed support) disturbs.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..core import settings
from ..core.bodies import DYNAMIC, KINEMATIC


def update_sleep(bodies, manifolds, h: float, overlapping: np.ndarray | None = None) -> None:
    """Advance rest timers, then put resting islands to sleep and wake disturbed ones.

    ``overlapping``: bodies with a contact deeper than ``SLEEP_MAX_PENETRATION``; they do
    not count as resting while the position solve separates them.
    """
    n = bodies.count
    dynamic = bodies.body_alive[:n] & (bodies.body_motion_type[:n] == DYNAMIC)
    awake = dynamic & bodies.body_awake[:n]
    if not awake.any():
        return  # nothing moves: every dynamic body sleeps and stays asleep
    speed_sq = np.sum(bodies.body_linear_velocity[:n] ** 2, axis=1)
    spin_sq = np.sum(bodies.body_angular_velocity[:n] ** 2, axis=1)
    slow = (speed_sq < settings.SLEEP_LINEAR_VELOCITY**2) & (
        spin_sq < settings.SLEEP_ANGULAR_VELOCITY**2
    )
    time = bodies.body_sleep_time[:n]
    resting = awake & slow
    time[resting] += h
    time[awake ^ resting] = 0.0  # the awake bodies that are not slow
    if overlapping is not None:
        time[overlapping] = 0.0
    # a dynamic body touching a moving kinematic one is being pushed: it is not resting
    pushing = moving_kinematic_mask(bodies, n)
    if pushing.any():
        a, b = _touching_pairs(manifolds)
        time[a[dynamic[a] & pushing[b]]] = 0.0
        time[b[dynamic[b] & pushing[a]]] = 0.0
    if not (awake & (time >= settings.TIME_TO_SLEEP)).any() and not (dynamic ^ awake).any():
        return  # no body rested long enough and none sleeps: the islands change nothing
    pairs = manifolds.bodies[manifolds.rows_with_points()]  # (m, 2) touching bodies
    joined = dynamic[pairs].all(axis=1)  # dynamic-dynamic contacts join islands
    labels = _island_labels(n, pairs[joined])
    island_rest = np.full(n, np.inf)
    np.minimum.at(island_rest, labels[dynamic], time[dynamic])
    asleep = dynamic & (island_rest[labels] >= settings.TIME_TO_SLEEP)
    falling_asleep = asleep & bodies.body_awake[:n]
    bodies.body_linear_velocity[:n][falling_asleep] = 0.0
    bodies.body_angular_velocity[:n][falling_asleep] = 0.0
    woken = dynamic & ~asleep & ~bodies.body_awake[:n]
    time[woken] = 0.0
    bodies.body_awake[:n] = np.where(dynamic, ~asleep, bodies.body_awake[:n])


def moving_kinematic_mask(bodies, n: int) -> np.ndarray:
    """(n,) bool: KINEMATIC bodies with a non-zero velocity-control velocity."""
    kinematic = bodies.body_motion_type[:n] == KINEMATIC
    if not kinematic.any():
        return kinematic  # no kinematic body (most scenes): none moves
    moving = (bodies.body_solver_velocity[:n] != 0).any(1) | (
        bodies.body_solver_angular_velocity[:n] != 0
    ).any(1)
    return kinematic & moving


def _touching_pairs(manifolds) -> tuple[np.ndarray, np.ndarray]:
    """Bodies ``a, b (m,)`` of the manifolds holding at least one point."""
    rows = manifolds.rows_with_points()
    return manifolds.bodies[rows, 0], manifolds.bodies[rows, 1]


def _island_labels(n: int, pairs: np.ndarray) -> np.ndarray:
    """Connected-component label ``(n,)`` of every body; ``pairs (e, 2)`` are the edges."""
    if len(pairs) == 0:
        return np.arange(n)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    return connected_components(graph, directed=False)[1]


def wake_touched(bodies, manifolds) -> bool:
    """Wake sleeping dynamic bodies touching an awake dynamic or a moving kinematic body.

    Runs right after collision detection, so the solver already treats a body that was hit
    this step as movable (otherwise it would act as a wall for one step). Returns True when a
    body was woken.
    """
    n = bodies.count
    pairs = manifolds.bodies[manifolds.rows_with_points()]  # (m, 2) touching bodies
    dynamic = bodies.body_motion_type[:n] == DYNAMIC
    sleeping = dynamic & ~bodies.body_awake[:n]
    sleeper = sleeping[pairs]  # (m, 2)
    if not sleeper.any():
        return False
    # a sleeper wakes when its partner is an awake dynamic body or a moving kinematic one
    disturbing = (dynamic & bodies.body_awake[:n]) | moving_kinematic_mask(bodies, n)
    partner_disturbs = disturbing[pairs][:, ::-1]  # (m, 2): the other body of each pair
    woken = pairs[sleeper & partner_disturbs]
    bodies.body_awake[woken] = True
    bodies.body_sleep_time[woken] = 0.0
    return len(woken) > 0


def wake_body(bodies, index: int) -> None:
    """Wake body ``index`` and restart its rest timer (a no-op for non-dynamic bodies)."""
    if bodies.body_motion_type[index] == DYNAMIC:
        bodies.body_awake[index] = True
        bodies.body_sleep_time[index] = 0.0


def wake_island(bodies, manifolds, index: int) -> None:
    """Wake the islands touching body ``index``: every dynamic body connected to it through
    contact manifolds (a support removed or moved lets the whole stack above move)."""
    neighbors: dict[int, list[int]] = {}
    for a, c in manifolds:
        neighbors.setdefault(a, []).append(c)
        neighbors.setdefault(c, []).append(a)
    frontier, seen = [index], {index}
    while frontier:
        current = frontier.pop()
        for other in neighbors.get(current, []):
            if other in seen or bodies.body_motion_type[other] != DYNAMIC:
                continue  # static and kinematic bodies do not join islands
            seen.add(other)
            wake_body(bodies, other)
            frontier.append(other)
