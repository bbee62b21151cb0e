"""Graph coloring of contact manifolds (Box2D v3 ``constraint_graph.c`` idea).

Manifolds in one color touch distinct *dynamic* bodies, so the solver can update all of
them with one batch of NumPy operations and still be Gauss-Seidel between colors (each
color sees the velocities written by the previous one). Static and kinematic bodies have
infinite mass: the solver never writes their velocity, so they do not constrain colors.
"""

from __future__ import annotations

import numpy as np


def color_manifolds(body_a: np.ndarray, body_b: np.ndarray, is_dynamic: np.ndarray) -> list:
    """Greedy coloring of manifolds: each takes the lowest color that neither of its dynamic
    bodies uses yet (the colors a body uses are the set bits of one Python int, so a body
    may have any number of colors).

    Parameters
    ----------
    body_a, body_b : (m,) int, the two bodies of each manifold.
    is_dynamic : (n,) bool, bodies whose velocity the solver changes.

    Returns
    -------
    list of (k_c,) int arrays, the manifold indices of each color, in increasing order.
    """
    m, n = len(body_a), len(is_dynamic)
    if m == 0:
        return []
    # a body the solver does not move constrains no color: it is replaced by a slot of its
    # own (n + manifold index) that no other manifold shares, so the loop needs no test
    own = n + np.arange(m)
    slot_a = np.where(is_dynamic[body_a], body_a, own).tolist()
    slot_b = np.where(is_dynamic[body_b], body_b, own).tolist()
    # used[s]: bit c is set when slot s already has a manifold of color c
    used = [0] * (n + m)
    bits = []
    for a, b in zip(slot_a, slot_b, strict=True):
        taken = used[a] | used[b]
        bit = ~taken & (taken + 1)  # the lowest color neither uses, as a bit
        used[a] |= bit
        used[b] |= bit
        bits.append(bit)
    color = np.array(list(map(int.bit_length, bits)), dtype=np.int64) - 1
    order = np.argsort(color, kind="stable")  # by color, manifold order kept inside one
    stops = np.cumsum(np.bincount(color))
    return np.split(order, stops[:-1])
