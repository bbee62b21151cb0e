"""Start-up hook of ``rigidsim-habitat-alias`` (run by ``rigidsim_habitat_alias.pth``).

``register()`` puts a deferred finder on ``sys.meta_path``. It does nothing, and imports
nothing, until a module named ``habitat_sim``, ``magnum`` or ``corrade`` (or one under them)
is imported; then, once, it calls rigidsim's
``engine.habitat_compat.alias.install_at_startup()``, which installs the alias unless a real
Habitat-sim, Magnum or Corrade is importable (then it warns and the real package loads), and
hands the import over to the alias. So interpreter start-up stays as fast as without the
hook, and ``pip`` keeps working whatever state rigidsim is in.
"""

from __future__ import annotations

import importlib.abc
import importlib.machinery
import importlib.util
import sys
import warnings
from collections.abc import Sequence
from types import ModuleType

__all__ = ["register"]

_ROOTS = ("habitat_sim", "magnum", "corrade")


class _DeferredAlias(importlib.abc.MetaPathFinder):
    """Installs rigidsim's alias on the first import of one of the aliased names."""

    def __init__(self) -> None:
        self.decided = False  # True once install_at_startup ran (or rigidsim was missing)

    def find_spec(
        self,
        fullname: str,
        path: Sequence[str] | None = None,
        target: ModuleType | None = None,
    ) -> importlib.machinery.ModuleSpec | None:
        if self.decided or fullname.partition(".")[0] not in _ROOTS:
            return None
        self.decided = True  # before the install, whose own look-ups come back here
        try:
            from engine.habitat_compat import alias
        except ImportError as error:
            warnings.warn(
                f"rigidsim-habitat-alias is installed but rigidsim's engine cannot be imported "
                f"({error}); install rigidsim (pip install . in its checkout) or uninstall "
                f"rigidsim-habitat-alias",
                RuntimeWarning,
                stacklevel=2,
            )
            return None
        if not alias.install_at_startup():
            return None
        # the first aliased import is always a top-level name (parents load first); the
        # alias's finder, now at the head of sys.meta_path, answers it
        return importlib.util.find_spec(fullname)


def register() -> None:
    """Put the deferred finder on ``sys.meta_path`` (once per process)."""
    if not any(isinstance(finder, _DeferredAlias) for finder in sys.meta_path):
        sys.meta_path.insert(0, _DeferredAlias())
