"""Size budgets of the renderer, in one place.

Every image rigidsim allocates is refused up front, with a ``ValueError`` naming the budget,
when it would hold more pixels than :data:`MAX_PIXELS`; a typo such as a 100000 x 100000
camera then fails at once instead of exhausting memory in the rasterizer (which keeps several
full-size buffers: depth keys, depth, color, ids, per-pixel shading inputs; about 100 bytes
per pixel at the peak).
"""

from __future__ import annotations

#: pixels, the largest image (camera sensor, video frame) rigidsim allocates: 4096 x 4096,
#: about 1.7 GB at the rasterizer's peak of roughly 100 bytes per pixel.
MAX_PIXELS = 4096 * 4096


def check_pixel_budget(height: int, width: int, what: str) -> None:
    """Raise ValueError naming ``what`` and the budget when ``height x width`` exceeds it."""
    if int(height) * int(width) > MAX_PIXELS:
        raise ValueError(
            f"{what} of {int(height)} x {int(width)} pixels exceeds the render budget "
            f"render.settings.MAX_PIXELS = {MAX_PIXELS} (4096 x 4096)"
        )
