"""Built-in primitive asset templates (Habitat's ``PrimitiveAssetAttributes``).

A primitive template is known by its handle, which also holds its construction parameters,
``key_value`` pairs after the Magnum class prefix: ``capsule3DSolid_hemiRings_4_cylRings_1_
segments_12_halfLen_0.75_useTexCoords_false_useTangents_false``. The properties read and
write those pairs (validated); :meth:`PrimitiveAssetAttributes.build_handle` writes them
back into the handle; :attr:`~PrimitiveAssetAttributes.is_valid_template` applies Magnum's
rules.
"""

from __future__ import annotations

from typing import Any

from engine.templates.base import AbstractAttributes, Field, validate

__all__ = ["PRIMITIVE_FIELDS", "PrimitiveAssetAttributes"]


PRIMITIVE_FIELDS: dict[str, Field] = {}
_PRIMITIVE_FLAGS = ("useTexCoords", "useTangents", "capEnd", "capEnds")


class PrimitiveAssetAttributes(AbstractAttributes):
    """A built-in primitive asset (Magnum primitive) known by its handle, e.g. ``cubeSolid``.

    ``primitive_class`` is the Magnum class name (``cubeSolid`` -> ``Cube``); ``is_wireframe``
    tells the wireframe variants (rendered and collided as their solid surface in rigidsim).
    """

    FIELDS = PRIMITIVE_FIELDS

    def __init__(self, handle: str = "") -> None:
        super().__init__(handle)
        prefix, _, rest = handle.partition("_")
        tokens = rest.split("_") if rest else []
        params = {key: value for key, value in zip(tokens[0::2], tokens[1::2], strict=False)}
        object.__setattr__(self, "_prefix", prefix)
        object.__setattr__(self, "_params", params)

    # -- construction parameters (Habitat's names; each is one ``key_value`` of the handle) --
    def _param(self, key: str, kind: type) -> Any:
        text = self._params.get(key)
        if text is None:
            raise AttributeError(f"{self._prefix} templates have no {key!r} parameter")
        if kind is bool:
            return text == "true"
        return kind(float(text)) if kind is int else kind(text)

    def _set_param(self, key: str, value: Any, kind: type) -> None:
        if key not in self._params:
            raise AttributeError(f"{self._prefix} templates have no {key!r} parameter")
        if kind is bool:
            self._params[key] = "true" if validate(key, "bool", value) else "false"
        elif kind is int:
            self._params[key] = str(validate(key, "int", value))
        else:
            self._params[key] = f"{validate(key, 'positive', value):g}"

    num_segments = property(
        lambda self: self._param("segments", int),
        lambda self, v: self._set_param("segments", v, int),
    )
    num_rings = property(
        lambda self: self._param("rings", int), lambda self, v: self._set_param("rings", v, int)
    )
    half_length = property(
        lambda self: self._param("halfLen", float),
        lambda self, v: self._set_param("halfLen", v, float),
    )
    hemisphere_rings = property(
        lambda self: self._param("hemiRings", int),
        lambda self, v: self._set_param("hemiRings", v, int),
    )
    cylinder_rings = property(
        lambda self: self._param("cylRings", int),
        lambda self, v: self._set_param("cylRings", v, int),
    )
    subdivisions = property(
        lambda self: self._param("subdivs", int), lambda self, v: self._set_param("subdivs", v, int)
    )
    use_texture_coords = property(
        lambda self: self._param("useTexCoords", bool),
        lambda self, v: self._set_param("useTexCoords", v, bool),
    )
    use_tangents = property(
        lambda self: self._param("useTangents", bool),
        lambda self, v: self._set_param("useTangents", v, bool),
    )
    use_cap_end = property(
        lambda self: self._param("capEnd", bool), lambda self, v: self._set_param("capEnd", v, bool)
    )
    use_cap_ends = property(
        lambda self: self._param("capEnds", bool),
        lambda self, v: self._set_param("capEnds", v, bool),
    )

    def build_handle(self) -> str:
        """Rebuild the handle from the parameters (Habitat's ``build_handle``)."""
        pairs = "".join(f"_{key}_{value}" for key, value in self._params.items())
        self.handle = f"{self._prefix}{pairs}"
        return self.handle

    @property
    def is_valid_template(self) -> bool:
        """Whether Magnum can build the primitive (Habitat's rules): solid primitives need
        ``segments >= 3``, wireframes ``segments >= 4`` and a multiple of 4; rings and capsule
        rings ``>= 1``; UV spheres ``rings >= 2`` (even for wireframes); subdivisions >= 0."""
        p = {
            key: self._param(
                key, bool if key in _PRIMITIVE_FLAGS else (float if key == "halfLen" else int)
            )
            for key in self._params
        }
        wire = self.is_wireframe
        if "segments" in p:
            if wire and (p["segments"] < 4 or p["segments"] % 4):
                return False
            if not wire and p["segments"] < 3:
                return False
        minimum_rings = 2 if self._prefix.startswith("uvSphere") else 1
        if p.get("rings", minimum_rings) < minimum_rings:
            return False
        if wire and self._prefix.startswith("uvSphere") and p["rings"] % 2:
            return False
        if min(p.get("hemiRings", 1), p.get("cylRings", 1)) < 1 or p.get("subdivs", 0) < 0:
            return False
        return p.get("halfLen", 1.0) > 0.0

    @property
    def primitive_class(self) -> str:
        names = {
            "capsule3D": "Capsule3D",
            "cone": "Cone",
            "cube": "Cube",
            "cylinder": "Cylinder",
            "icosphere": "Icosphere",
            "uvSphere": "UVSphere",
        }
        for prefix, name in names.items():
            if self.handle.startswith(prefix):
                return name
        raise ValueError(f"not a primitive handle: {self.handle!r}")

    @property
    def is_wireframe(self) -> bool:
        return "Wireframe" in self._prefix

    @property
    def template_class(self) -> str:
        """Habitat's class key: ``CapsulePrimitiveAttributes``, ``CubePrimitiveAttributes``..."""
        return f"{self.primitive_class.removesuffix('3D')}PrimitiveAttributes"

    @property
    def prim_obj_class_name(self) -> str:
        """Habitat's name for the Magnum primitive class (``primitive_class``)."""
        return self.primitive_class
