"""Fixed-field objects: assigning an unknown attribute raises, naming the closest field.

Habitat's configuration, template and object classes are C++ bindings with a fixed set of
fields, so ``template.frictoin_coefficient = 0.3`` raises ``AttributeError`` there instead of
silently creating a new Python attribute that nothing reads. rigidsim's Python classes do the
same through :func:`unknown_attribute_error`, which suggests the closest known name
(``difflib.get_close_matches``, similarity ratio >= 0.6).
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable

__all__ = ["public_names", "unknown_attribute_error"]


def public_names(cls: type) -> list[str]:
    """Names of the public attributes, properties and methods of ``cls`` (and its bases)."""
    return sorted({name for klass in cls.__mro__ for name in vars(klass)
                   if not name.startswith("_")})


def unknown_attribute_error(owner: str, name: str, known: Iterable[str]) -> AttributeError:
    """An ``AttributeError`` saying ``owner`` has no field ``name``, with the closest match."""
    close = difflib.get_close_matches(name, list(known), n=1)
    hint = f"; did you mean {close[0]!r}?" if close else ""
    return AttributeError(f"{owner} has no attribute {name!r}{hint}")
