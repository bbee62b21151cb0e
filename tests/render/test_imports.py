"""render is a leaf library: it never imports engine or navmesh (docs/conventions.md)."""

from __future__ import annotations

import ast
from pathlib import Path

from import_graph_support import strongly_connected_groups

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


# ------------------------------------------------------------------------------------------
# no import cycle at run time, imports inside functions included
# ------------------------------------------------------------------------------------------
REPOSITORY = RENDER_DIR.parent
PACKAGES = ("engine", "render", "navmesh")


def module_files() -> dict[str, Path]:
    """Dotted module name -> file of every module of the three packages."""
    modules = {}
    for package in PACKAGES:
        for path in sorted((REPOSITORY / package).rglob("*.py")):
            parts = path.relative_to(REPOSITORY).with_suffix("").parts
            if parts[-1] == "__init__":
                parts = parts[:-1]
            modules[".".join(parts)] = path
    return modules


def runtime_imports(tree: ast.AST):
    """Every import statement that can run: all of them, at any depth (inside functions
    too), except the bodies of ``if TYPE_CHECKING:`` blocks."""
    for node in ast.iter_child_nodes(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            yield from (n for child in node.orelse for n in runtime_imports_of(child))
            continue
        yield from runtime_imports_of(node)


def runtime_imports_of(node: ast.AST):
    if isinstance(node, ast.Import | ast.ImportFrom):
        yield node
    yield from runtime_imports(node)


def imported_modules(name: str, path: Path, modules: dict[str, Path]) -> set[str]:
    """The project modules that importing module ``name`` runs directly: each imported
    module, a ``from package import submodule``'s submodule, and the packages on the way
    (their ``__init__`` runs first) unless they enclose ``name`` (already running)."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in runtime_imports(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        else:
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(anchor + ([base] if base else []))
            targets = [f"{base}.{alias.name}" for alias in node.names]
            targets = [t if t in modules else base for t in targets]
        for target in targets:
            parts = target.split(".")
            for end in range(1, len(parts) + 1):
                module = ".".join(parts[:end])
                encloses = name == module or name.startswith(module + ".")
                if module in modules and not encloses:
                    found.add(module)
    return found


def test_the_import_graph_finds_a_function_level_cycle(tmp_path):
    modules = {"a": tmp_path / "a.py", "b": tmp_path / "b.py"}
    modules["a"].write_text("import b\n")
    modules["b"].write_text("def late():\n    from a import x\n")
    graph = {name: imported_modules(name, path, modules) for name, path in modules.items()}
    assert strongly_connected_groups(graph) == [["a", "b"]]
    modules["b"].write_text("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    import a\n")
    graph = {name: imported_modules(name, path, modules) for name, path in modules.items()}
    assert strongly_connected_groups(graph) == []


def test_no_import_cycles_at_run_time():
    modules = module_files()
    assert len(modules) > 100
    graph = {name: imported_modules(name, path, modules) for name, path in modules.items()}
    assert (
        "engine.physics.pipeline.reference_contacts"
        in graph["engine.physics.pipeline.collision_stage"]
    )
    assert strongly_connected_groups(graph) == []
