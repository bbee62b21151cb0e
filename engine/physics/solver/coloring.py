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
    bodies uses yet (the colors a body uses are the set bits of one Python int).

    Parameters
    ----------
    body_a, body_b : (m,) int, the two bodies of each manifold.
    is_dynamic : (n,) bool, bodies whose velocity the solver changes.

    Returns
    -------
    list of (k_c,) int arrays, the manifold indices of each color, in increasing order.
    """
    colors: list[list[int]] = []
    # used[b]: bit c is set when dynamic body b already has a manifold of color c
    used = [0] * len(is_dynamic)
    dyn_a, dyn_b = is_dynamic[body_a].tolist(), is_dynamic[body_b].tolist()
    for index, (a, b) in enumerate(zip(body_a.tolist(), body_b.tolist(), strict=True)):
        taken = (used[a] if dyn_a[index] else 0) | (used[b] if dyn_b[index] else 0)
        color = (~taken & (taken + 1)).bit_length() - 1  # the lowest color neither uses
        if color == len(colors):
            colors.append([])
        colors[color].append(index)
        if dyn_a[index]:
            used[a] |= 1 << color
        if dyn_b[index]:
            used[b] |= 1 << color
    return [np.array(c, dtype=np.int64) for c in colors]
