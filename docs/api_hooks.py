"""Sphinx hooks of the API reference (a local extension that ``docs/conf.py`` loads).

Three rules, each keeping what a reader sees true to the code:

* **Every object is described once**, in the section of the module that defines it (the API
  pages use autodoc's ``:ignore-module-all:``). A module whose ``__all__`` exports names of
  other modules (``engine.Simulator``, ``navmesh.PathFinder``) gets a line of links to their
  descriptions instead of a second copy of each.
* **A name in a type means what it means in that module.** A type written in a docstring
  field (``parts : list of Part``) or moved there from an annotation is looked up by Sphinx
  "fuzzily", by suffix: ``Part`` would match every ``*.Part`` and ``object`` the attribute
  ``RenderCamera.object``. Here a name the module imports resolves to the object the module
  imports; any other name is looked up exactly (a builtin stays plain text).
* **An attribute's ``#:`` comment is prose.** Napoleon reads a first line ``a: b`` of an
  attribute's docstring as "type ``a``, description ``b``"; rigidsim's comments
  (``#: m, clipping tolerance: ...``) are sentences, kept as written.
"""

from __future__ import annotations

import inspect
import sys
from typing import Any, TypeVar

from sphinx import addnodes

PROSE_WHAT = ("attribute", "data", "property")
_attribute_docstrings: dict[str, list[str]] = {}


def export_reference(name: str, value: object) -> str:
    """A link to where ``value``, exported as ``name``, is described (its defining module)."""
    target = qualified_name(value)
    if target is None:
        return f"``{name}``"
    return f":py:{'mod' if inspect.ismodule(value) else 'obj'}:`{name} <{target}>`"


def list_exports(
    app: Any, what: str, name: str, obj: object, options: Any, lines: list[str]
) -> None:
    """Append to a module's docstring the names its ``__all__`` exports from other modules."""
    if what != "module" or not isinstance(getattr(obj, "__all__", None), (list, tuple)):
        return
    exported = []
    for export in obj.__all__:
        value = getattr(obj, export, None)
        defined_here = getattr(value, "__module__", None) == name and not inspect.ismodule(value)
        if value is not None and not defined_here:
            exported.append(export_reference(export, value))
    if exported:
        lines += ["", f"Exported from other modules: {', '.join(exported)}.", ""]


def keep_attribute_prose(
    app: Any, what: str, name: str, obj: object, options: Any, lines: list[str]
) -> None:
    """Before napoleon: remember an attribute's docstring as written."""
    if what in PROSE_WHAT:
        _attribute_docstrings[name] = list(lines)


def restore_attribute_prose(
    app: Any, what: str, name: str, obj: object, options: Any, lines: list[str]
) -> None:
    """After napoleon: put the attribute's docstring back as written."""
    if what in PROSE_WHAT and name in _attribute_docstrings:
        lines[:] = _attribute_docstrings.pop(name)


def qualified_name(value: object) -> str | None:
    """``module.qualname`` of a class, function or module, else None."""
    if inspect.ismodule(value):
        return value.__name__
    module, qualname = getattr(value, "__module__", None), getattr(value, "__qualname__", None)
    if isinstance(module, str) and isinstance(qualname, str) and "<" not in qualname:
        return f"{module}.{qualname}"
    return None


def resolve_type_names(app: Any, doctree: Any) -> None:
    """Turn Sphinx's suffix search for a type's name into Python's name resolution."""
    for node in doctree.findall(addnodes.pending_xref):
        if node.get("refdomain") != "py" or not node.hasattr("refspecific"):
            continue
        target = node.get("reftarget", "")
        if "." in target:
            continue
        module = sys.modules.get(node.get("py:module") or "")
        found = qualified_name(getattr(module, target, None)) if module else None
        if found is not None:
            node["reftarget"] = found
        del node["refspecific"]  # exact lookup: its presence asks for the suffix search
        node[TYPE_FIELD] = True


def lookup(path: str) -> object:
    """The object a dotted path names when Python follows it from one of rigidsim's packages
    (``navmesh.PathFinder`` is ``navmesh.pathfinder.PathFinder``); None when it names nothing."""
    parts = path.split(".")
    if parts[0] not in PACKAGES:
        return None
    value: object = sys.modules.get(parts[0])
    for depth, part in enumerate(parts[1:], start=2):
        submodule = sys.modules.get(".".join(parts[:depth]))
        value = submodule if submodule is not None else getattr(value, part, None)
        if value is None:
            return None
    return value


def defining_class(owner: object, name: str) -> type | None:
    """The class of ``owner``'s MRO that defines or annotates ``name``, else None."""
    for klass in getattr(owner, "__mro__", ()):
        if name in vars(klass) or name in getattr(klass, "__annotations__", {}):
            return klass
    return None


def candidates_for(target: str, module: str, owner: str) -> list[str]:
    """Dotted paths ``target`` may mean, seen from ``module`` (and its class ``owner``)."""
    parts = module.split(".")
    paths = [".".join([*parts[:depth], target]) for depth in range(len(parts), 0, -1)]
    paths.append(target)
    if owner:
        paths.insert(0, f"{module}.{owner}.{target}")
    return paths


def resolve_within_package(app: Any, env: Any, node: Any, contnode: Any) -> Any:
    """Resolve what Sphinx could not, or leave it as plain text where no page can describe it.

    Called for every reference Sphinx did not find (``missing-reference``). A name is looked up
    as Python would: relative to the module's class and package (``:mod:`pair_table``` in
    ``engine.physics.collision``), then through imports (``navmesh.PathFinder``), then as the
    one object of the same top package whose name ends with it (a module moved to another
    folder is still found). Left as plain text, since no page describes them: types of fields
    and bases outside rigidsim (no inventory of NumPy's or Python's docs is read offline),
    private names, type variables, names a class inherits from outside rigidsim (Gymnasium's
    ``render_mode``) and names that exist but have no description (a constant without a
    ``#:`` comment). What remains is a reference to a name that does not exist (a typo, a
    module moved away): the build warns (``nitpicky``), and fails.
    """
    if node.get("refdomain") != "py":
        return None
    target = node.get("reftarget", "").lstrip("~.")
    external = target.split(".")[0] not in PACKAGES
    if node.get(TYPE_FIELD) or target.split(".")[-1].startswith("_"):
        return contnode
    if external and node.get("reftype") in ("class", "obj", "exc"):
        return contnode
    domain = env.domains["py"]
    module, owner = node.get("py:module") or "", node.get("py:class") or ""
    exists = False  # the name is in the code, though no page may describe it
    for path in candidates_for(target, module, owner):
        value = lookup(path)
        exists = exists or value is not None
        found = path if path in domain.objects else qualified_name(value)
        if isinstance(value, TypeVar):
            return contnode
        if found in domain.objects:
            return domain.resolve_xref(
                env, node["refdoc"], app.builder, node["reftype"], found, node, contnode
            )
    definer = defining_class(lookup(f"{module}.{owner}") if owner else None, target)
    if definer is not None and definer.__module__.split(".")[0] not in PACKAGES:
        return contnode  # inherited from outside rigidsim
    top = target.split(".")[0] if not external else module.split(".")[0]
    kinds = set(domain.objtypes_for_role(node["reftype"]) or ())
    for tail in dict.fromkeys([target, target.split(".")[-1]]):  # whole name, then last part
        start, end = f"{top}.", f".{tail}"
        ending = [
            name
            for name, entry in domain.objects.items()
            if name.startswith(start) and name.endswith(end) and entry.objtype in kinds
        ]
        if len(ending) == 1:
            return domain.resolve_xref(
                env, node["refdoc"], app.builder, node["reftype"], ending[0], node, contnode
            )
    return contnode if exists else None  # an undescribed constant stays plain text


PACKAGES = ("engine", "render", "navmesh")
TYPE_FIELD = "rigidsim_type_field"


def setup(app: Any) -> dict[str, Any]:
    app.connect("autodoc-process-docstring", list_exports)
    app.connect("autodoc-process-docstring", keep_attribute_prose, priority=100)
    app.connect("autodoc-process-docstring", restore_attribute_prose, priority=900)
    app.connect("doctree-read", resolve_type_names)
    app.connect("missing-reference", resolve_within_package)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
