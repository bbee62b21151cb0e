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
from typing import Any

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


def resolve_within_package(app: Any, env: Any, node: Any, contnode: Any) -> Any:
    """Resolve what Sphinx could not, or leave it as plain text where no page can describe it.

    Called for every reference Sphinx did not find (``missing-reference``): a name written
    relative to the module's package (``:mod:`pair_table``` in ``engine.physics``) is looked
    up in the module's package, then its parents, then as the one object of the same top
    package whose name ends with it (so a module that moves to another folder is still
    found). Types (field types, base classes) outside rigidsim's packages stay plain text:
    no inventory of NumPy's or Python's docs is read offline. What remains is a reference
    into rigidsim that names nothing: the build warns (``nitpicky``), and fails.
    """
    if node.get("refdomain") != "py":
        return None
    target = node.get("reftarget", "").lstrip("~.")
    if node.get(TYPE_FIELD) or (
        node.get("reftype") in ("class", "obj", "exc") and target.split(".")[0] not in PACKAGES
    ):
        return contnode
    domain = env.domains["py"]
    module = node.get("py:module") or ""
    parts = module.split(".")
    candidates = [".".join([*parts[:depth], target]) for depth in range(len(parts), 0, -1)]
    top = parts[0] if parts[0] in PACKAGES else None
    if top is not None:
        start, end = f"{top}.", f".{target}"
        suffix = [name for name in domain.objects if name.startswith(start) and name.endswith(end)]
        candidates += suffix if len(suffix) == 1 else []
    for candidate in candidates:
        if candidate in domain.objects:
            return domain.resolve_xref(
                env, node["refdoc"], app.builder, node["reftype"], candidate, node, contnode
            )
    return None


PACKAGES = ("engine", "render", "navmesh")
TYPE_FIELD = "rigidsim_type_field"


def setup(app: Any) -> dict[str, Any]:
    app.connect("autodoc-process-docstring", list_exports)
    app.connect("autodoc-process-docstring", keep_attribute_prose, priority=100)
    app.connect("autodoc-process-docstring", restore_attribute_prose, priority=900)
    app.connect("doctree-read", resolve_type_names)
    app.connect("missing-reference", resolve_within_package)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
