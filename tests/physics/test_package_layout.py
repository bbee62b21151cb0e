"""The folders of ``engine/physics/`` import only downward, and no module imports itself back.

Every import of every module counts here, those under ``if TYPE_CHECKING:`` and those inside
functions included (a type-hint import is still a dependency a reader has to follow). The
layering, lowest first, is the one ``engine/physics/__init__.py`` states: ``core``, then
``collision`` and ``solver`` (independent of each other), ``reference``, ``pipeline``,
``objects``, and the root (``world.py``, ``__init__.py``).
"""

from __future__ import annotations

import ast
from pathlib import Path

from import_graph_support import strongly_connected_groups

PHYSICS = Path(__file__).resolve().parents[2] / "engine" / "physics"
#: folder -> layer (a folder may import only folders of a lower layer)
LAYERS = {"core": 1, "collision": 2, "solver": 2, "reference": 3, "pipeline": 4, "objects": 5}
ROOT_LAYER = 6


def module_name(path: Path) -> str:
    parts = path.relative_to(PHYSICS.parents[1]).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def physics_imports(path: Path, modules: set[str]) -> set[str]:
    """The ``engine.physics`` modules that ``path`` imports anywhere in its text."""
    name = module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(anchor + ([base] if base else []))
            targets = [f"{base}.{alias.name}" for alias in node.names]
            targets = [t if t in modules else base for t in targets]
        else:
            continue
        found |= {t for t in targets if t in modules and t != name}
    return found


def import_graph() -> dict[str, set[str]]:
    paths = {module_name(p): p for p in PHYSICS.rglob("*.py")}
    return {name: physics_imports(path, set(paths)) for name, path in paths.items()}


def folder_of(module: str) -> str | None:
    """The folder of a module (None for the root: ``engine.physics``, ``world``)."""
    parts = module.split(".")
    return parts[2] if len(parts) > 2 and parts[2] in LAYERS else None


def test_every_folder_is_in_the_layering() -> None:
    folders = {p.name for p in PHYSICS.iterdir() if (p / "__init__.py").is_file()}
    assert folders == set(LAYERS)
    assert {p.name for p in PHYSICS.glob("*.py")} == {"__init__.py", "world.py"}


def test_no_import_circle_inside_engine_physics_type_hints_included() -> None:
    graph = import_graph()
    assert len(graph) > 50
    # the three circles this layout broke are found if they come back
    assert (
        "engine.physics.collision.collision_objects"
        in graph["engine.physics.pipeline.narrow_phase"]
    )
    assert strongly_connected_groups(graph) == []


def test_a_type_hint_circle_is_found() -> None:
    graph = import_graph()
    graph["engine.physics.objects.physics_object"].add("engine.physics.world")  # as before
    assert any("engine.physics.world" in group for group in strongly_connected_groups(graph))


def test_folders_import_only_lower_layers() -> None:
    wrong = []
    for module, targets in import_graph().items():
        layer = LAYERS.get(folder_of(module) or "", ROOT_LAYER)
        for target in targets:
            folder = folder_of(target)
            if folder is None or folder == folder_of(module):
                if folder is None and layer != ROOT_LAYER:
                    wrong.append(f"{module} -> {target}")  # a folder importing the root
                continue
            if LAYERS[folder] >= layer:
                wrong.append(f"{module} -> {target}")
    assert wrong == []


def test_no_physics_file_over_500_lines() -> None:
    long = {
        p.relative_to(PHYSICS).as_posix(): n
        for p in PHYSICS.rglob("*.py")
        if (n := len(p.read_text(encoding="utf-8").splitlines())) > 500
    }
    assert long == {}
