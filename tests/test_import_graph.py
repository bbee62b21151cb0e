"""No import circle anywhere in engine, render or navmesh, type-hint imports included.

The import graph is grimp's (the library import-linter checks the contracts of
``pyproject.toml`` with): one node per module, one edge per ``import`` statement anywhere in
the module (inside functions and ``if TYPE_CHECKING:`` blocks too). A circle is a strongly
connected group of more than one module (Tarjan's algorithm); the test names every such group
and the imports that close it, so a new circle is found with the line to change. A type that
two modules both need lives in a module below both (``render/buffers.py`` for
``FrameBuffers``, imported by ``render/frame.py`` and ``render/deferred.py``).
"""

from __future__ import annotations

import sys
from pathlib import Path

import grimp
import pytest
from import_graph_support import strongly_connected_groups

PACKAGES = ("engine", "render", "navmesh")


def import_edges(graph: grimp.ImportGraph) -> dict[str, set[str]]:
    """Module -> the modules it imports (any import statement, type hints included)."""
    return {m: set(graph.find_modules_directly_imported_by(m)) for m in graph.modules}


def describe(group: list[str], edges: dict[str, set[str]]) -> str:
    """One circle: its modules and the imports between them."""
    inside = set(group)
    lines = [f"{a} -> {b}" for a in group for b in sorted(edges[a] & inside)]
    return f"circle of {len(group)} modules:\n    " + "\n    ".join(lines)


def test_no_import_circles_in_engine_render_navmesh() -> None:
    graph = grimp.build_graph(*PACKAGES, exclude_type_checking_imports=False, cache_dir=None)
    assert "engine.physics" in graph.modules and "render.frame" in graph.modules
    edges = import_edges(graph)
    groups = strongly_connected_groups(edges)
    assert groups == [], "\n".join(describe(group, edges) for group in groups)


def test_the_finder_names_a_circle_made_of_a_type_hint_import(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    package = tmp_path / "circlepkg"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "a.py").write_text("from circlepkg.b import B\n\nclass A(B):\n    pass\n")
    (package / "b.py").write_text(
        "from typing import TYPE_CHECKING\n\nif TYPE_CHECKING:\n    from circlepkg.a import A\n"
        "\n\nclass B:\n    pass\n"
    )
    (package / "c.py").write_text("import circlepkg.a\n")  # imports the circle, is not in it
    monkeypatch.syspath_prepend(str(tmp_path))
    graph = grimp.build_graph("circlepkg", cache_dir=None)
    edges = import_edges(graph)
    assert strongly_connected_groups(edges) == [["circlepkg.a", "circlepkg.b"]]
    text = describe(["circlepkg.a", "circlepkg.b"], edges)
    assert "circlepkg.a -> circlepkg.b" in text and "circlepkg.b -> circlepkg.a" in text
    sys.modules.pop("circlepkg", None)


def test_the_finder_keeps_separate_circles_apart() -> None:
    edges = {"a": {"b"}, "b": {"a", "c"}, "c": {"d"}, "d": {"c"}, "e": {"a"}}
    assert sorted(strongly_connected_groups(edges)) == [["a", "b"], ["c", "d"]]
