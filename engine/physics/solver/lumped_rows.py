"""One lumped normal row per manifold: the rows of the stage-priority sweeps.

:class:`LumpedRows` holds each manifold's contact points lumped into one normal row
(``J = mean_i J_i``, ``W = mean_i W_i``, ``m_eff = 1 / (J W^T)``). The stage-priority pass
(:mod:`engine.physics.solver.stage_priority`) makes and sweeps them; the solver's per-batch
cache (:class:`engine.physics.solver.contact_batch.SolverCache`) keeps them between sweeps.
The type lives here, below both, so that neither imports the other for it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.settings import TINY

__all__ = ["LumpedRows"]


@dataclass
class LumpedRows:
    """Each manifold's points lumped into one normal row (see :func:`lumped_rows`):
    ``jac (m, 1, 12)``, ``w (m, 12, 1)``, ``neg_mass (m, 1, 1)`` (``-m_eff``), the points'
    averaging ``weight (m, S)``, ``bias (m, 1, 1)``, and the products the sweeps use,
    ``scaled_jac`` ``-m_eff J`` and ``mass_bias`` ``-m_eff b``."""

    jac: np.ndarray
    w: np.ndarray
    neg_mass: np.ndarray
    weight: np.ndarray
    scaled_jac: np.ndarray
    bias: np.ndarray | None = None
    mass_bias: np.ndarray | None = None

    @classmethod
    def of(cls, normal_jac, normal_w, active) -> LumpedRows:
        """``J = mean_i J_i``, ``W = mean_i W_i`` over the ``active (m, S)`` points."""
        count = np.maximum(active.sum(axis=1), 1)[:, None]
        chosen = active[:, None, :].astype(np.float64)  # (m, 1, S), 1 for the active points
        # the sums over the active points as stacked matmuls, then / count
        jac = (chosen @ normal_jac)[:, 0] / count  # (m, 12)
        w = (normal_w @ np.swapaxes(chosen, 1, 2))[..., 0] / count  # (m, 12)
        return cls.with_mobility(jac, w, active.any(axis=1), active / count)

    @classmethod
    def with_mobility(cls, jac, w, active, weight) -> LumpedRows:
        """Rows ``jac``, ``w (m, 12)``; ``m_eff = 1 / (J W^T)`` where ``active (m,)`` and
        ``J W^T > 0``, else 0."""
        k = (jac * w).sum(axis=1)  # J W^T
        neg_mass = np.where(active & (k > 0), -1.0 / np.maximum(k, TINY), 0.0)[:, None, None]
        jac = jac[:, None, :]
        return cls(jac, w[:, :, None], neg_mass, weight, neg_mass * jac)

    def with_bias(self, bias: np.ndarray) -> LumpedRows:
        """The rows with the mean of their points' biases ``bias (m, S, 1)``."""
        row_bias = (bias[..., 0] * self.weight).sum(axis=1)[:, None, None]
        return LumpedRows(
            self.jac,
            self.w,
            self.neg_mass,
            self.weight,
            self.scaled_jac,
            row_bias,
            self.neg_mass * row_bias,
        )
