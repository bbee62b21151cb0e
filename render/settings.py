"""Render settings as one frozen value, and the size budgets of the renderer.

:class:`RenderSettings` holds every knob that selects a code path or a working-set size of
:func:`render.render_frame`: triangle batches, fragment chunks, shading bands, and the
switches between the fast kernels and their plain readable versions. It is a frozen
dataclass passed with each render (``render_frame(..., settings=...)``, each job of the
render worker): no module globals, so a worker process renders with exactly the settings
of the job it was given. Every combination gives the same pixels bit for bit (the tests
render with :data:`DEFAULT_SETTINGS` and with :meth:`RenderSettings.plain`); only the time
spent changes.

Size budgets: every image rigidsim allocates is refused up front, with a ``ValueError``
naming the budget, when it would hold more pixels than :data:`MAX_PIXELS`; a typo such as a
100000 x 100000 camera then fails at once instead of exhausting memory in the rasterizer
(which keeps several full-size buffers: depth keys, depth, color, ids, per-pixel shading
inputs; about 100 bytes per pixel at the peak).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

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


@dataclass(frozen=True)
class RenderSettings:
    """Working-set sizes and kernel switches of one render (frozen: hashable, picklable).

    Attributes
    ----------
    triangle_batch : triangles rasterized per batch (stages 3-6): per-triangle temporaries
        stay in the CPU cache.
    fragment_chunk : fragments expanded and depth-tested per chunk (stage 6): 16k
        temporaries stay in the cache (3x faster than 200k).
    refine_used_above : stage 7 builds shading inputs for all candidate triangles up to this
        many; above, only for those that drew fragments, and if those are still more, only
        for the pixel winners.
    shade_band_pixels : pixels resolved and shaded per band of rows (stage 8): 16k. 32k was
        4 % faster for ``render_frame`` alone but slower in most runs inside the simulator.
    fast_shading : True: ``shade_pixels`` uses the in-place packed kernels
        (``sample_bilinear_fast``, lighting of every pixel without gathers); False: the
        plain ones (``sample_bilinear``, lighting of the pixels with ``light < 1`` only).
    light_all_above : with ``fast_shading``, light every pixel in place (``light == 1``
        leaves a color unchanged) when at least this fraction of them is lit; below, gather
        and scatter the lit ones.
    sample_all_above : with ``fast_shading`` and one texture, sample it at every pixel (then
        keep the textured ones) when at least this fraction of the pixels is textured.
    pixel_center_tables : True: pixel-center coordinates are read from cached per-camera
        tables; False: computed with ``divmod`` (same values).
    paired_attributes : True: two-channel attributes (uvs) are interpolated as one
        complex64; False: channel by channel (same bits).
    """

    triangle_batch: int = 8_192
    fragment_chunk: int = 16_384
    refine_used_above: int = 8_192
    shade_band_pixels: int = 16_384
    fast_shading: bool = True
    light_all_above: float = 0.25
    sample_all_above: float = 0.5
    pixel_center_tables: bool = True
    paired_attributes: bool = True

    def __post_init__(self) -> None:
        for field in dataclasses.fields(self):
            value = getattr(self, field.name)
            if field.type == "int" and not (
                isinstance(value, int) and not isinstance(value, bool) and value >= 1
            ):
                raise ValueError(f"RenderSettings.{field.name} must be an int >= 1, got {value!r}")
            if field.type == "bool" and not isinstance(value, bool):
                raise ValueError(f"RenderSettings.{field.name} must be a bool, got {value!r}")
            if field.type == "float" and not (
                isinstance(value, (int, float)) and not isinstance(value, bool) and 0 <= value <= 1
            ):
                raise ValueError(
                    f"RenderSettings.{field.name} must be a fraction in [0, 1], got {value!r}"
                )

    @classmethod
    def plain(cls, **changes: object) -> RenderSettings:
        """The plain readable kernels everywhere (the fast ones' switches off)."""
        values: dict = {"fast_shading": False, "pixel_center_tables": False}
        values["paired_attributes"] = False
        values.update(changes)
        return cls(**values)

    def replace(self, **changes: object) -> RenderSettings:
        """A copy with ``changes`` (checked like a new value)."""
        return dataclasses.replace(self, **changes)  # type: ignore[arg-type]


#: the settings of a render when none are given
DEFAULT_SETTINGS = RenderSettings()
