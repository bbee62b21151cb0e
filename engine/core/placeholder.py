"""Honest placeholders: Habitat names that rigidsim has no feature behind.

Habitat code (habitat-lab above all) imports names of features rigidsim does not have
(articulated objects, the batch replay renderer, Magnum's mesh importers) and uses them in
annotations at import time, long before, or without ever, using them. Such a name must exist
to import; using it must fail loudly. So:

- a :class:`Placeholder` class imports, annotates, subclasses and ``isinstance``-checks like
  any class, but constructing it, or reading a public attribute off it
  (``SimulatorBackend.reset(sim)``), raises :class:`NotImplementedError`;
- a :class:`PlaceholderObject` is an object Habitat creates at import time
  (``magnum.trade.ImporterManager()`` in habitat-lab's receptacle module): it constructs, and
  every public attribute read on it raises;
- :func:`placeholder_function` makes a function that raises when called.

Every message names the Habitat name, what rigidsim lacks and what it offers instead.
Private and dunder attributes raise the ordinary ``AttributeError``, so ``hasattr`` probes,
``typing`` and documentation tools keep working.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, ClassVar, NoReturn

__all__ = ["Placeholder", "PlaceholderObject", "not_in_rigidsim", "placeholder_function"]


def not_in_rigidsim(habitat_name: str, missing: str, instead: str) -> NotImplementedError:
    """The error every placeholder raises: the name, what rigidsim lacks, what it offers."""
    return NotImplementedError(
        f"{habitat_name} is a placeholder in rigidsim: {missing}. Instead: {instead}."
    )


class _PlaceholderMeta(type):
    """Reading a public attribute a placeholder class does not define raises the
    placeholder's error (``SimulatorBackend.reset(sim)``), not an ``AttributeError``."""

    def __getattr__(cls, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        raise cls._error(f".{name}")  # type: ignore[attr-defined]


class Placeholder(metaclass=_PlaceholderMeta):
    """Base of a Habitat class that rigidsim has no feature behind (module docstring).

    A subclass sets ``habitat_name`` (its full Habitat path), ``missing`` (what rigidsim
    lacks) and ``instead`` (what rigidsim offers in its place).
    """

    habitat_name: ClassVar[str] = ""
    missing: ClassVar[str] = ""
    instead: ClassVar[str] = ""

    @classmethod
    def _error(cls, member: str = "") -> NotImplementedError:
        return not_in_rigidsim(f"{cls.habitat_name}{member}", cls.missing, cls.instead)

    def __new__(cls, *args: Any, **kwargs: Any) -> NoReturn:
        raise cls._error("()")


class PlaceholderObject:
    """An object Habitat code creates at import time; every public attribute read raises.

    A subclass sets the same three class attributes as :class:`Placeholder`.
    """

    habitat_name: ClassVar[str] = ""
    missing: ClassVar[str] = ""
    instead: ClassVar[str] = ""

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        raise not_in_rigidsim(f"{self.habitat_name}.{name}", self.missing, self.instead)

    def __repr__(self) -> str:
        return f"<{self.habitat_name} placeholder: {self.missing}>"


def placeholder_function(
    habitat_name: str, missing: str, instead: str, *, module: str
) -> Callable[..., NoReturn]:
    """A function named after ``habitat_name`` that raises the placeholder error when called;
    ``module`` is the module that exports it (its ``__name__``), so documentation and
    introspection find it there."""

    def placeholder(*args: Any, **kwargs: Any) -> NoReturn:
        raise not_in_rigidsim(habitat_name, missing, instead)

    placeholder.__name__ = habitat_name.rpartition(".")[2]
    placeholder.__qualname__ = placeholder.__name__
    placeholder.__module__ = module
    placeholder.__doc__ = f"Placeholder of ``{habitat_name}``: {missing}; raises when called."
    return placeholder
