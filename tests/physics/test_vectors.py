"""``core.vectors``: NumPy's ``np.vecdot``, the written-out sum (its NumPy 1.x fallback) and
``dot`` (either, by operand size) give the same numbers, bit for bit, on the short axes
the collision kernels use."""

from __future__ import annotations

import numpy as np
import pytest

from engine.physics.core import vectors


@pytest.mark.parametrize("shape", [(3,), (7, 3), (5, 4, 2), (6, 1, 3), (9, 8, 4), (150, 24, 3)])
def test_the_fallback_sums_the_same_products_as_numpy(shape: tuple[int, ...]) -> None:
    rng = np.random.default_rng(len(shape) * 10 + shape[-1])
    u = rng.normal(size=shape) * 10.0 ** rng.integers(-3, 4, size=shape)
    v = rng.normal(size=shape[-1:])  # broadcast over the leading axes, as the kernels do
    fallback = vectors.summed_products(u, v)
    assert fallback.shape == shape[:-1]
    np.testing.assert_array_equal(vectors.vecdot(u, v), fallback)
    np.testing.assert_array_equal(vectors.dot(u, v), fallback)
    # and both are the dot product
    np.testing.assert_allclose(fallback, np.einsum("...k,k->...", u, v), rtol=1e-12, atol=1e-12)


def test_vecdot_is_numpys_where_numpy_has_it() -> None:
    if hasattr(np, "vecdot"):
        assert vectors.vecdot is np.vecdot
    else:
        assert vectors.vecdot is vectors.summed_products
