"""The opt-in import alias: ``habitat_sim`` -> :mod:`engine`, ``magnum`` -> :mod:`engine.mn`,
``corrade`` -> :mod:`engine.habitat_compat.corrade`.

Unchanged Habitat code (habitat-lab, a Habitat-sim tutorial) writes ``import habitat_sim`` and
``import magnum as mn``. After :func:`install`, those imports give rigidsim's modules::

    from engine.habitat_compat import alias
    alias.install()
    import habitat_sim, magnum
    assert habitat_sim.physics is engine.physics and magnum.Vector3 is engine.mn.Vector3

How (the import protocol of PEP 451): :func:`install` puts a finder at the head of
``sys.meta_path``. Asked for a name under one of the three roots, the finder works out the
rigidsim module that stands for it: the same dotted tail under the root's target
(``habitat_sim.physics`` -> ``engine.physics``, ``magnum.trade`` -> ``engine.mn.trade``), or,
for the few Habitat modules rigidsim keeps under another name, the entry of
:data:`RENAMED_MODULES` (``habitat_sim.sim`` -> ``engine.habitat_compat.sim``). Its loader
imports that module and hands the import system the **same module object**, which
``sys.modules`` then holds under both names; so classes are identical
(``habitat_sim.Simulator is engine.Simulator``) and ``isinstance`` works across the two
spellings. The import system overwrites ``__spec__`` of a module it loads; the loader puts
the module's own spec back, so the rigidsim module keeps its own name for ``importlib.reload``
and for tools that read it.

Never shadowing a real install: while the alias is not installed, :func:`install` asks the
import system whether a real ``habitat_sim``, ``magnum`` or ``corrade`` can be imported (a
module with a location on ``sys.path``) or is already imported. If so it raises
:class:`AliasConflictError` naming where that module lives; ``install(force=True)`` installs
anyway (the alias then wins over the real package for every later import), except over a
module already imported, which no finder can replace.

:func:`install_at_startup` is what the separate distribution ``rigidsim-habitat-alias``
(``scripts/habitat_alias``) calls from its ``.pth`` file: the same install, but a conflict
only warns and leaves the real package in place; ``RIGIDSIM_HABITAT_ALIAS=off`` disables
it, ``RIGIDSIM_HABITAT_ALIAS=force`` forces it.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import importlib.util
import os
import sys
import warnings
from collections.abc import Sequence
from types import ModuleType

__all__ = [
    "ALIAS_ROOTS",
    "RENAMED_MODULES",
    "AliasConflictError",
    "findable_real_packages",
    "imported_real_packages",
    "install",
    "install_at_startup",
    "is_installed",
    "rigidsim_name",
    "uninstall",
]

#: Habitat's top-level module -> the rigidsim module that stands for it
ALIAS_ROOTS = {
    "habitat_sim": "engine",
    "magnum": "engine.mn",
    "corrade": "engine.habitat_compat.corrade",
}
#: Habitat modules that rigidsim keeps under another name (their submodules follow them)
RENAMED_MODULES = {
    "habitat_sim._ext": "engine.habitat_compat.ext",
    "habitat_sim._ext.habitat_sim_bindings": "engine.bindings",
    "habitat_sim.sim": "engine.habitat_compat.sim",
}
#: the environment variable read by :func:`install_at_startup`
ENVIRONMENT_SWITCH = "RIGIDSIM_HABITAT_ALIAS"


class AliasConflictError(ImportError):
    """A real Habitat-sim, Magnum or Corrade is importable, so the alias is not installed."""


def rigidsim_name(habitat_name: str) -> str | None:
    """The rigidsim module that stands for ``habitat_name``, or None outside the alias.

    The longest prefix found in :data:`RENAMED_MODULES` or :data:`ALIAS_ROOTS` is replaced by
    its target: ``habitat_sim.utils.common`` -> ``engine.utils.common``.
    """
    parts = habitat_name.split(".")
    for length in range(len(parts), 0, -1):
        prefix = ".".join(parts[:length])
        target = RENAMED_MODULES.get(prefix) or ALIAS_ROOTS.get(prefix)
        if target is not None:
            return ".".join([target, *parts[length:]])
    return None


class _AliasLoader(importlib.abc.Loader):
    """Hands the import system an already imported rigidsim module (module docstring)."""

    def __init__(self, target: str) -> None:
        self.target = target
        self._target_spec: importlib.machinery.ModuleSpec | None = None

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> ModuleType:
        module = importlib.import_module(self.target)
        self._target_spec = module.__spec__
        return module

    def exec_module(self, module: ModuleType) -> None:
        # the import system set module.__spec__ to the alias spec; give the module its own back
        module.__spec__ = self._target_spec


class _AliasFinder(importlib.abc.MetaPathFinder):
    """The ``sys.meta_path`` entry of the alias; remembers the names it served."""

    def __init__(self) -> None:
        self.served: set[str] = set()

    def find_spec(
        self,
        fullname: str,
        path: Sequence[str] | None = None,
        target: ModuleType | None = None,
    ) -> importlib.machinery.ModuleSpec | None:
        rigidsim_module = rigidsim_name(fullname)
        if rigidsim_module is None:
            return None
        try:
            target_spec = importlib.util.find_spec(rigidsim_module)
        except ModuleNotFoundError:  # a parent of the target is missing
            return None
        if target_spec is None:  # no such rigidsim module: the import fails as usual
            return None
        self.served.add(fullname)
        is_package = target_spec.submodule_search_locations is not None
        return importlib.machinery.ModuleSpec(
            fullname, _AliasLoader(rigidsim_module), is_package=is_package
        )


_FINDER = _AliasFinder()


def is_installed() -> bool:
    """True while the alias's finder is on ``sys.meta_path``."""
    return _FINDER in sys.meta_path


def imported_real_packages() -> list[str]:
    """Habitat's top-level modules already imported from a real package (not by the alias)."""
    return [name for name in ALIAS_ROOTS if name in sys.modules and name not in _FINDER.served]


def findable_real_packages() -> dict[str, str]:
    """Habitat's top-level modules a real package provides: name -> its file.

    A namespace folder without files does not count. Call only while the alias is not
    installed (it would find itself).
    """
    found: dict[str, str] = {}
    for name in ALIAS_ROOTS:
        if name in sys.modules:
            continue
        spec = importlib.util.find_spec(name)
        if spec is not None and spec.origin not in (None, "namespace"):
            found[name] = spec.origin
    return found


def install(force: bool = False) -> None:
    """Install the alias (module docstring); does nothing when it is installed already.

    Raises :class:`AliasConflictError` naming the real package when a real ``habitat_sim``,
    ``magnum`` or ``corrade`` is importable, unless ``force``; a real one already imported
    raises even then (no finder can replace it).
    """
    if is_installed():
        return
    imported = imported_real_packages()
    if imported:
        where = ", ".join(
            f"{name} from {getattr(sys.modules[name], '__file__', '?')}" for name in imported
        )
        raise AliasConflictError(
            f"rigidsim's habitat_sim/magnum/corrade alias not installed: a real package is "
            f"already imported ({where}); install the alias before importing it, in a "
            f"process without the real package"
        )
    findable = findable_real_packages()
    if findable and not force:
        where = ", ".join(f"{name} at {origin}" for name, origin in findable.items())
        raise AliasConflictError(
            f"rigidsim's habitat_sim/magnum/corrade alias not installed: a real package is "
            f"importable ({where}); use that installation, uninstall it, or call "
            f"install(force=True) to let rigidsim's modules win for every later import"
        )
    if not is_installed():  # the look-ups above may have run the start-up hook, which installs
        sys.meta_path.insert(0, _FINDER)


def uninstall() -> None:
    """Remove the alias: its finder and the module names it served from ``sys.modules``
    (the rigidsim modules themselves stay imported under their own names)."""
    while _FINDER in sys.meta_path:
        sys.meta_path.remove(_FINDER)
    for name in _FINDER.served:
        sys.modules.pop(name, None)
    _FINDER.served.clear()


def install_at_startup() -> bool:
    """The ``.pth`` hook's install: True when the alias is on.

    ``RIGIDSIM_HABITAT_ALIAS=off`` (or ``0``) leaves it off; ``=force`` installs over a real
    package. A conflict warns (``RuntimeWarning``) and leaves the real package in place.
    """
    switch = os.environ.get(ENVIRONMENT_SWITCH, "").strip().lower()
    if switch in {"off", "0", "false", "no"}:
        return False
    try:
        install(force=switch == "force")
    except AliasConflictError as error:
        warnings.warn(
            f"{error} ({ENVIRONMENT_SWITCH}=force forces it)", RuntimeWarning, stacklevel=2
        )
        return False
    return True
