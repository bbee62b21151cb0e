"""``NamedIntEnum``: an integer enum that prints its name, as Habitat's (pybind11) enums do.

Python's ``IntEnum`` prints its number (``str(MotionType.DYNAMIC) == "2"`` since 3.11);
Habitat's enums print ``MotionType.DYNAMIC``, and Habitat programs print them in logs. Members
still compare and compute as integers (``MotionType.DYNAMIC == 2``).
"""

from __future__ import annotations

import enum

__all__ = ["NamedIntEnum"]


class NamedIntEnum(enum.IntEnum):
    """An ``IntEnum`` whose ``str`` and ``format`` give ``ClassName.MEMBER``."""

    def __str__(self) -> str:
        return f"{type(self).__name__}.{self.name}"

    def __format__(self, format_spec: str) -> str:
        return format(str(self), format_spec)
