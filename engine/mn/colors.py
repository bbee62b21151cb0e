"""Colors of :mod:`engine.mn`: Magnum's ``Color3`` (RGB) and ``Color4`` (RGBA).

Channels are linear floats, usually in [0, 1] (a ``Color3`` is a ``Vector3``, a ``Color4`` a
``Vector4``). The named constructors are Magnum's: ``red(r=1)`` is ``(r, 0, 0)``, ``cyan(r=0)``
is ``(r, 1, 1)``, ``magenta(g=0)`` is ``(1, g, 1)``, ``yellow(b=0)`` is ``(1, 1, b)``; the
``Color4`` ones take ``alpha`` last. From integers: ``from_linear_rgb_int(0xRRGGBB)`` divides
each byte by 255 as is; ``from_srgb_int(0xRRGGBB)`` also undoes the sRGB transfer curve
(``c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4``). ``from_xyz`` converts CIE XYZ
(D65) to linear sRGB with the standard matrix.
"""

from __future__ import annotations

import inspect
from typing import Any

import numpy as np

from engine.mn.vectors import Vector3, Vector4, finite_array, is_scalar

__all__ = ["Color3", "Color4"]

#: CIE XYZ (D65) -> linear sRGB, rows r, g, b (IEC 61966-2-1)
XYZ_TO_LINEAR_RGB = np.array(
    [
        [3.2404542, -1.5371385, -0.4985314],
        [-0.9692660, 1.8760108, 0.0415560],
        [0.0556434, -0.2040259, 1.0572252],
    ]
)


def _bytes_of(value: Any, count: int, name: str) -> np.ndarray:
    """The ``count`` bytes of an integer, most significant first, as floats in [0, 1]."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise TypeError(f"{name} must be an int such as 0xff8800, got {value!r}")
    if not 0 <= int(value) < 256**count:
        raise ValueError(f"{name} must be in [0, 0x{'ff' * count}], got {value!r}")
    shifts = 8 * np.arange(count - 1, -1, -1)
    return ((int(value) >> shifts) & 0xFF) / 255.0


def srgb_to_linear(channels: np.ndarray) -> np.ndarray:
    """Undo the sRGB transfer curve, channel by channel (inputs and outputs in [0, 1])."""
    return np.where(channels <= 0.04045, channels / 12.92, ((channels + 0.055) / 1.055) ** 2.4)


#: Magnum's named colors: name -> (the channel its one argument sets, that argument's default).
#: The other two channels are ``1 - default``: ``red(red=1)`` is ``(red, 0, 0)``, ``cyan(red=0)``
#: is ``(red, 1, 1)``. The argument is named after its channel.
NAMED_COLORS = {
    "red": (0, 1.0),
    "green": (1, 1.0),
    "blue": (2, 1.0),
    "cyan": (0, 0.0),
    "magenta": (1, 0.0),
    "yellow": (2, 0.0),
}
CHANNEL_NAMES = ("red", "green", "blue")


def named_color(name: str, alpha: bool) -> Any:
    """The static constructor ``Color3.<name>(channel=default)`` or, with ``alpha``,
    ``Color4.<name>(channel=default, alpha=1.0)`` of :data:`NAMED_COLORS`."""
    channel, default = NAMED_COLORS[name]
    parameters = [
        inspect.Parameter(
            CHANNEL_NAMES[channel], inspect.Parameter.POSITIONAL_OR_KEYWORD, default=default
        )
    ]
    if alpha:
        parameters.append(
            inspect.Parameter("alpha", inspect.Parameter.POSITIONAL_OR_KEYWORD, default=1.0)
        )
    signature = inspect.Signature(parameters)

    def constructor(*args: Any, **kwargs: Any) -> Vector3:
        bound = signature.bind(*args, **kwargs)
        bound.apply_defaults()
        value, *rest = bound.arguments.values()
        rgb = [1.0 - default] * 3
        rgb[channel] = value
        return Color4(*rgb, *rest) if alpha else Color3(*rgb)

    constructor.__name__ = constructor.__qualname__ = name
    constructor.__signature__ = signature  # type: ignore[attr-defined]
    constructor.__doc__ = f"Magnum's ``{name}``: see :data:`NAMED_COLORS`."
    return staticmethod(constructor)


class Color3(Vector3):
    """An RGB color with float channels in [0, 1] (Magnum's ``Color3``, a ``Vector3``)."""

    __slots__ = ()

    r = Vector3.x
    g = Vector3.y
    b = Vector3.z

    red = named_color("red", alpha=False)
    green = named_color("green", alpha=False)
    blue = named_color("blue", alpha=False)
    cyan = named_color("cyan", alpha=False)
    magenta = named_color("magenta", alpha=False)
    yellow = named_color("yellow", alpha=False)

    @staticmethod
    def from_linear_rgb_int(linear: int) -> Color3:
        """``0xRRGGBB`` with each byte divided by 255 (no transfer curve)."""
        return Color3(_bytes_of(linear, 3, "linear"))

    @staticmethod
    def from_srgb_int(srgb: int) -> Color3:
        """``0xRRGGBB`` in sRGB, converted to linear channels."""
        return Color3(srgb_to_linear(_bytes_of(srgb, 3, "srgb")))

    @staticmethod
    def from_xyz(xyz: Any) -> Color3:
        """CIE XYZ (D65) to linear RGB."""
        return Color3(XYZ_TO_LINEAR_RGB @ finite_array(xyz, 3, "xyz"))


class Color4(Vector4):
    """An RGBA color (Magnum's ``Color4``); alpha defaults to 1: ``Color4(r, g, b)``,
    ``Color4(Color3(...))``, ``Color4(Color3(...), a)``, ``Color4(gray)``."""

    __slots__ = ()

    def __init__(self, *values: Any) -> None:
        if len(values) == 1 and is_scalar(values[0]):
            values = (float(values[0]),) * 3 + (1.0,)
        elif len(values) == 1 and len(np.asarray(values[0]).reshape(-1)) == 3:
            values = (values[0], 1.0)
        elif len(values) == 3:
            values = (*values, 1.0)
        super().__init__(*values)

    r = Vector3.x
    g = Vector3.y
    b = Vector3.z
    a = Vector4.w

    @property
    def rgb(self) -> Color3:
        return Color3(self._data[:3])

    red = named_color("red", alpha=True)
    green = named_color("green", alpha=True)
    blue = named_color("blue", alpha=True)
    cyan = named_color("cyan", alpha=True)
    magenta = named_color("magenta", alpha=True)
    yellow = named_color("yellow", alpha=True)

    @staticmethod
    def from_linear_rgb_int(linear: int, a: float = 1.0) -> Color4:
        """``0xRRGGBB`` with each byte divided by 255, alpha ``a``."""
        return Color4(Color3.from_linear_rgb_int(linear), a)

    @staticmethod
    def from_linear_rgba_int(linear: int) -> Color4:
        """``0xRRGGBBAA`` with each byte divided by 255."""
        return Color4(_bytes_of(linear, 4, "linear"))

    @staticmethod
    def from_srgb_int(srgb: int, a: float = 1.0) -> Color4:
        """``0xRRGGBB`` in sRGB, converted to linear channels, alpha ``a``."""
        return Color4(Color3.from_srgb_int(srgb), a)

    @staticmethod
    def from_xyz(xyz: Any, a: float = 1.0) -> Color4:
        """CIE XYZ (D65) to linear RGB, alpha ``a``."""
        return Color4(Color3.from_xyz(xyz), a)
