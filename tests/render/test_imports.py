"""render is a leaf library: it never imports engine or navmesh (docs/conventions.md)."""

from __future__ import annotations

import ast
from pathlib import Path

RENDER_DIR = Path(__file__).resolve().parents[2] / "render"


def imported_top_level_packages(path: Path) -> set[str]:
    """Top-level package names imported by a Python file (absolute imports)."""
    names = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            names |= {alias.name.split(".")[0] for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names.add(node.module.split(".")[0])
    return names


def test_render_never_imports_engine_or_navmesh():
    files = sorted(RENDER_DIR.glob("*.py"))
    assert len(files) >= 6
    for path in files:
        forbidden = imported_top_level_packages(path) & {"engine", "navmesh"}
        assert not forbidden, f"{path.name} imports {forbidden}"
