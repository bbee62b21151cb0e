"""Habitat's light setups (``habitat_sim.gfx``): ``LightInfo``, ``LightPositionModel`` and the
setup keys, turned into the rasterizer's :class:`render.shade.Lights` arrays.

A light setup is a list of :class:`LightInfo` stored in the simulator under a string key
(``sim.set_light_setup(lights, key)``, ``sim.get_light_setup(key)``; the store is
:class:`LightSetups`). Every drawable names the key it is lit by: objects
``DEFAULT_LIGHTING_KEY`` unless added with another ``light_setup_key``, the stage
``sim_cfg.scene_light_setup`` (``NO_LIGHT_KEY`` by default: drawn flat, as Habitat draws
it). An empty setup is flat shading.

``LightInfo.vector`` is homogeneous: ``w = 0`` a directional light shining from direction
``(x, y, z)``, ``w = 1`` a point light at ``(x, y, z)``. ``model`` says which frame the
vector is in: ``Global`` (world), ``Camera`` (the rendering camera's frame, so the light
moves with the camera) or ``Object`` (the lit object's frame). Shading (see
:mod:`render.shade`)::

    light = clamp(0.4 + sum_k c_k max(0, n . l_k), 0, 1),   c_k = mean(color_k)

rigidsim's rasterizer modulates a pixel by one gray factor, so a light's color acts through
its mean intensity (a deliberate difference, in the README). rigidsim's default setup keeps
its historic 4 directional lights of intensity 0.5 (Habitat 0.3's default is 5 lights tuned
for its PBR shader).

``DebugLineRender`` (``sim.get_debug_line_render()``) is importable from here as in Habitat; it
is :class:`engine.sensors.debug_lines.DebugLineRender`, resolved on first use.
"""

from __future__ import annotations

import importlib
from typing import Any

import numpy as np

from engine import mn
from engine.core.fixed_fields import unknown_attribute_error
from engine.core.named_enum import NamedIntEnum
from render.lights import AMBIENT, DEFAULT_LIGHTS, Lights

__all__ = [
    "DEFAULT_LIGHTING_KEY",
    "NO_LIGHT_KEY",
    "LightInfo",
    "LightPositionModel",
    "LightSetups",
    "default_light_setup",
    "to_render_lights",
]

#: key of the setup objects are lit by unless told otherwise (Habitat's value)
DEFAULT_LIGHTING_KEY = ""
#: key of the always-empty setup: flat shading (Habitat's value)
NO_LIGHT_KEY = "no_lights"


class LightPositionModel(NamedIntEnum):
    """The frame a light's vector is given in (Habitat's enum)."""

    Camera = 0
    Global = 1
    Object = 2


_FRAME = {
    LightPositionModel.Global: "world",
    LightPositionModel.Camera: "camera",
    LightPositionModel.Object: "mesh",
}
_FIELDS = ("vector", "color", "model")


class LightInfo:
    """One light: ``vector`` (Vector4, w = 0 directional / 1 point), ``color`` (Color3,
    white by default), ``model`` (``LightPositionModel.Global`` by default)."""

    __slots__ = ("_vector", "_color", "_model")
    # the checked values, stored by __setattr__ (read through the properties below)
    _vector: mn.Vector4
    _color: mn.Color3
    _model: LightPositionModel

    def __init__(
        self,
        vector: Any = (0.0, 0.0, 1.0, 0.0),
        color: Any = (1.0, 1.0, 1.0),
        model: LightPositionModel = LightPositionModel.Global,
    ) -> None:
        self.vector = vector
        self.color = color
        self.model = model

    def __setattr__(self, name: str, value: Any) -> None:
        if name == "vector":
            array = np.asarray(value, dtype=np.float64).reshape(-1)
            if array.shape != (4,) or not np.all(np.isfinite(array)):
                raise ValueError(f"LightInfo.vector must be a finite 4-vector, got {value!r}")
            if array[3] not in (0.0, 1.0):
                raise ValueError(
                    "LightInfo.vector needs w == 0 (directional) or w == 1 "
                    f"(point), got {array.tolist()}"
                )
            object.__setattr__(self, "_vector", mn.Vector4(array))
        elif name == "color":
            object.__setattr__(self, "_color", mn.Color3(mn.to_vector3(value, "LightInfo.color")))
        elif name == "model":
            object.__setattr__(self, "_model", LightPositionModel(int(value)))
        else:
            raise unknown_attribute_error("LightInfo", name, _FIELDS)

    vector = property(lambda self: mn.Vector4(np.asarray(self._vector)))
    color = property(lambda self: mn.Color3(np.asarray(self._color)))
    model = property(lambda self: self._model)

    def __eq__(self, other: object) -> bool:
        return (
            isinstance(other, LightInfo)
            and self._vector == other._vector
            and self._color == other._color
            and self._model == other._model
        )

    # No __hash__ (a mutable value): __eq__ alone sets it to None.

    def copy(self) -> LightInfo:
        return LightInfo(self.vector, self.color, self.model)

    def __repr__(self) -> str:
        return f"LightInfo(vector={self._vector!r}, color={self._color!r}, model={self._model!r})"


def default_light_setup() -> list[LightInfo]:
    """rigidsim's default setup as LightInfo: 4 directional gray lights (module docstring)."""
    return [
        LightInfo(vector, [intensity] * 3, LightPositionModel.Global)
        for vector, intensity in zip(
            DEFAULT_LIGHTS.vectors, DEFAULT_LIGHTS.intensities, strict=True
        )
    ]


def to_render_lights(setup: list[LightInfo]) -> Lights:
    """The rasterizer's arrays of a setup (``DEFAULT_LIGHTS`` itself for the default one,
    so the renderer keeps its exact historic formula)."""
    if setup == default_light_setup():
        return DEFAULT_LIGHTS
    vectors = np.array([np.asarray(light.vector) for light in setup]).reshape(-1, 4)
    intensities = np.array([float(np.mean(np.asarray(light.color))) for light in setup])
    frames = tuple(_FRAME[light.model] for light in setup)
    return Lights(vectors, intensities, frames, AMBIENT)


class LightSetups:
    """The simulator's light setups by key (``sim.set_light_setup`` / ``get_light_setup``)
    and the rasterizer's :class:`render.shade.Lights` of each, converted once per change.

    Starts with ``DEFAULT_LIGHTING_KEY`` (:func:`default_light_setup`) and ``NO_LIGHT_KEY``
    (always empty: flat shading).
    """

    def __init__(self) -> None:
        self._setups: dict[str, list[LightInfo]] = {
            DEFAULT_LIGHTING_KEY: default_light_setup(),
            NO_LIGHT_KEY: [],
        }
        self._render_lights = {key: to_render_lights(setup) for key, setup in self._setups.items()}

    def set(self, light_setup: list[LightInfo], key: str = DEFAULT_LIGHTING_KEY) -> None:
        """Store a copy of ``light_setup`` (a list of ``LightInfo``) under ``key``."""
        if not isinstance(key, str):
            raise TypeError(f"light setup key must be a str, got {key!r}")
        if key == NO_LIGHT_KEY:
            raise ValueError(f"the {NO_LIGHT_KEY!r} setup is always empty (flat shading)")
        setup = list(light_setup)
        for light in setup:
            if not isinstance(light, LightInfo):
                raise TypeError(f"a light setup holds LightInfo, got {type(light).__name__}")
        self._setups[key] = [light.copy() for light in setup]
        self._render_lights[key] = to_render_lights(self._setups[key])

    def get(self, key: str = DEFAULT_LIGHTING_KEY) -> list[LightInfo]:
        """A copy of the setup under ``key`` (an unknown key is an empty setup, as Habitat)."""
        return [light.copy() for light in self._setups.get(key, [])]

    def render_lights(self, key: str) -> Lights:
        """The renderer's arrays for a drawable's light setup key (unknown: flat)."""
        lights = self._render_lights.get(key)
        if lights is None:
            lights = self._render_lights.setdefault(key, to_render_lights([]))
        return lights


def __getattr__(name: str) -> Any:
    """Habitat's ``habitat_sim.gfx.DebugLineRender`` lives in :mod:`engine.sensors.debug_lines`
    (the sensors draw the lines); like :mod:`engine.bindings`, this face resolves it by name
    on first use, so the gfx module stays below the sensors."""
    if name == "DebugLineRender":
        return importlib.import_module("engine.sensors.debug_lines").DebugLineRender
    raise AttributeError(f"module 'engine.gfx' has no attribute {name!r}")
