"""Every module path the README and the docs name is a file of the repository.

The README's architecture section and the pages of ``docs/`` point readers to modules
(``engine/physics/pipeline/pair_table.py``, ``render/reference.py`` ...); a module renamed or
split leaves such a pointer dangling. This test collects every ``engine/``, ``render/``,
``navmesh/``, ``benchmarks/`` and ``scripts/`` path ending in ``.py`` (and every such folder
path ending in ``/``) written in ``README.md`` and ``docs/*.md`` and fails on one that does
not exist. Paths under ``tests/`` and ``examples/`` are left out: the docs also quote
Habitat-sim's own ``tests/test_sensors.py`` and a placeholder ``examples/NAME.py``. The
folder map of ``docs/physics.md`` must list each module of ``engine/physics/`` exactly once,
in the row of its folder, and the bare module names (`` `pair_table.py` ``) of the README
and the architecture pages (contacts, rendering, solver) must be files of the repository.
"""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("engine", "render", "navmesh", "benchmarks", "scripts")
# a path starts a word (not the tail of tests/engine/... or ../render/...)
PATH = re.compile(r"(?<![\w/.-])(?:" + "|".join(PACKAGES) + r")/(?:[\w-]+/)*(?:[\w-]+\.py)?")


def named_paths(text: str) -> set[str]:
    """The module files (``.py``) and folders (ending in ``/``) ``text`` names."""
    return {p for p in PATH.findall(text) if p.endswith((".py", "/"))}


def missing_paths(documents: list[Path]) -> list[str]:
    """``document: path`` for each named path that is not in the repository."""
    missing = []
    for document in documents:
        for path in sorted(named_paths(document.read_text(encoding="utf-8"))):
            if not (ROOT / path).exists():
                missing.append(f"{document.relative_to(ROOT)}: {path}")
    return missing


def test_every_module_path_in_the_readme_and_docs_exists() -> None:
    documents = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    missing = missing_paths(documents)
    assert missing == [], "named but not in the repository:\n" + "\n".join(missing)


#: pages whose bare module names (`` `pair_table.py` ``) must be files of the repository too
#: (others quote Habitat-sim's own files, ``test_gfx.py``)
BARE_NAME_PAGES = ("README.md", "docs/contacts.md", "docs/rendering.md", "docs/physics_solver.md")
FOLDERS = ("engine", "render", "navmesh", "benchmarks", "scripts", "tests", "examples")


def test_every_bare_module_name_of_the_architecture_pages_exists() -> None:
    files = {path.name for folder in FOLDERS for path in (ROOT / folder).rglob("*.py")}
    missing = [
        f"{page}: {name}"
        for page in BARE_NAME_PAGES
        for name in sorted(set(re.findall(r"`(\w+\.py)`", (ROOT / page).read_text("utf-8"))))
        if name not in files
    ]
    assert missing == [], "named but not in the repository:\n" + "\n".join(missing)


def test_the_readme_names_the_modules_it_is_checked_for() -> None:
    readme = named_paths((ROOT / "README.md").read_text(encoding="utf-8"))
    for path in ("engine/physics/world.py", "render/frame.py", "render/reference.py"):
        assert path in readme


def physics_map(page: str) -> dict[str, list[str]]:
    """The folder map of ``docs/physics.md``: the modules named in each folder's row."""
    start = page.index("## Where the code is")
    table = page[start : page.index("\n\n", page.index("| layer |", start))]
    rows = [line for line in table.splitlines() if line.startswith("| ")][1:]  # no header
    named: dict[str, list[str]] = {}
    for row in rows:
        cells = row.split("|")
        folder = re.findall(r"`(engine/physics/[\w/]*)`", cells[2])[0]
        named[folder] = re.findall(r"`(\w+\.py)`", cells[3])
    return named


def test_the_physics_page_maps_every_physics_module_exactly_once() -> None:
    named = physics_map((ROOT / "docs" / "physics.md").read_text(encoding="utf-8"))
    physics = ROOT / "engine" / "physics"
    folders = [physics, *sorted(p for p in physics.iterdir() if (p / "__init__.py").is_file())]
    assert sorted(named) == sorted(f"{f.relative_to(ROOT).as_posix()}/" for f in folders)
    for folder in folders:
        listed = named[f"{folder.relative_to(ROOT).as_posix()}/"]
        modules = sorted(p.name for p in folder.glob("*.py"))
        if folder != physics:
            modules.remove("__init__.py")  # the folder's map, not a module of the table
        assert sorted(listed) == modules, f"{folder.name}: {sorted(set(listed) ^ set(modules))}"
        assert len(listed) == len(set(listed)), f"{folder.name}: a module is listed twice"


def test_a_wrong_name_is_found(tmp_path: Path) -> None:
    page = ROOT / "docs" / "conventions.md"  # any real page, read with a wrong name appended
    text = page.read_text(encoding="utf-8") + "\nsee `engine/physics/pair_tabel.py` and "
    text += "render/no_such_folder/ but not tests/engine/test_x.py\n"
    wrong = tmp_path / "page.md"
    wrong.write_text(text, encoding="utf-8")
    paths = named_paths(wrong.read_text(encoding="utf-8"))
    assert "engine/physics/pair_tabel.py" in paths and "render/no_such_folder/" in paths
    assert not any(p.startswith("engine/test_x") for p in paths)
    assert sorted(p for p in paths if not (ROOT / p).exists()) == [
        "engine/physics/pair_tabel.py",
        "render/no_such_folder/",
    ]
