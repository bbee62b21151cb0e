"""Fixed-field configuration objects: a typo in an attribute name raises instead of passing.

Habitat's configuration classes (``SimulatorConfiguration``, ``CameraSensorSpec``,
``AgentConfiguration``, ``AgentState``, ``ActionSpec``...) are C++ structs or ``attrs`` classes
with slots, so ``sim_cfg.enable_phyiscs = True`` raises ``AttributeError``. Plain Python
objects would silently grow a new attribute and the typo would be ignored. :class:`FixedFields`
restores Habitat's behaviour: assigning a public name that is not a field of the class raises
``AttributeError`` naming the closest field (``difflib.get_close_matches``).

The known names of a class are its dataclass fields, the public attributes defined on the
class or its bases (properties, methods) and the names listed in ``_extra_fields``. Names
starting with ``_`` are private storage and always allowed. Templates, object wrappers,
light and constraint settings, which keep their fields elsewhere, raise the same error
through :func:`unknown_attribute_error` and :func:`public_names`.
"""

from __future__ import annotations

import dataclasses
import difflib
from collections.abc import Iterable
from typing import Any

__all__ = ["FixedFields", "public_names", "unknown_attribute_error"]


def public_names(cls: type) -> list[str]:
    """Names of the public attributes, properties and methods of ``cls`` (and its bases)."""
    return sorted(
        {name for klass in cls.__mro__ for name in vars(klass) if not name.startswith("_")}
    )


def unknown_attribute_error(class_name: str, name: str, known: Iterable[str]) -> AttributeError:
    """An ``AttributeError`` for ``class_name.name`` naming the closest known field, if any
    (``difflib.get_close_matches``, similarity ratio >= 0.6)."""
    known = list(known)
    close = difflib.get_close_matches(name, known, n=1)
    hint = f"; did you mean {close[0]!r}?" if close else f"; its fields are {sorted(known)}"
    return AttributeError(f"{class_name!r} object has no attribute {name!r}{hint}")


def _known_names(cls: type) -> frozenset[str]:
    """Every public name an instance of ``cls`` may be assigned (cached per class)."""
    cached = cls.__dict__.get("_known_names_cache")
    if cached is not None:
        return cached
    names = set(getattr(cls, "_extra_fields", ()))
    if dataclasses.is_dataclass(cls):
        names.update(f.name for f in dataclasses.fields(cls))
    for klass in cls.__mro__:
        names.update(n for n in vars(klass) if not n.startswith("_"))
    known = frozenset(names)
    type.__setattr__(cls, "_known_names_cache", known)
    return known


class FixedFields:
    """Mixin: ``__setattr__`` refuses public names that are not fields of the class."""

    def __setattr__(self, name: str, value: Any) -> None:
        if not name.startswith("_") and name not in _known_names(type(self)):
            known = [
                n for n in _known_names(type(self)) if not callable(getattr(type(self), n, None))
            ]
            raise unknown_attribute_error(type(self).__name__, name, known)
        object.__setattr__(self, name, value)
