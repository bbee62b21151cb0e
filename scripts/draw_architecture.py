"""Draw the layers of rigidsim from its import graph into ``docs/architecture.png``.

    python scripts/draw_architecture.py [--output docs/architecture.png]

The graph is grimp's (the library the import contracts of ``pyproject.toml`` are checked
with): every import statement of ``engine``, ``render`` and ``navmesh``, type-hint imports
included. Modules are grouped into boxes: one per folder of ``engine`` (``engine/sensors/``
...), one for Habitat's thin face modules on top (``engine/attributes.py`` ...), one for the
small Habitat modules (``engine/geo.py`` ...), one for the package face ``engine/__init__.py``,
and one each for ``render`` and ``navmesh``. A box's row is its height in the graph: the
longest chain of imports below it (leaf libraries at the bottom), so every arrow points
down; a box that imports no other box is raised to just under its lowest importer. Arrows are the
transitive reduction: ``a -> c`` is drawn only when no longer path ``a -> b -> c`` says it
already; the other direct imports are thin grey lines. ``engine/__init__.py`` resolves
Habitat's top-level names on first use (PEP 562), naming their modules in ``engine._LAZY``
and ``engine._SUBMODULES`` rather than importing them; those names are read from it and drawn
as dashed arrows, since they are imports that run.
"""

from __future__ import annotations

import argparse
import sys
from collections import defaultdict
from pathlib import Path

import grimp
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import FancyBboxPatch  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("engine", "render", "navmesh")
#: top-level modules of engine that only re-export Habitat's names from a folder
FACES = {"attributes", "attributes_managers", "metadata", "registry", "sensor"}
FACE_BOX = "faces: attributes(_managers),\nmetadata, registry, sensor"
SMALL_BOX = "gfx, geo, errors,\nlogging, bindings"
ROOT_BOX = "engine/__init__"


def box_of(module: str) -> str:
    """The box a module is drawn in."""
    parts = module.split(".")
    if parts[0] != "engine":
        return f"{parts[0]}/"
    if len(parts) == 1:
        return ROOT_BOX
    if (ROOT / "engine" / parts[1]).is_dir():
        return f"{parts[1]}/"
    return FACE_BOX if parts[1] in FACES else SMALL_BOX


def lazy_imports() -> set[str]:
    """The boxes ``engine/__init__.py`` imports on first use of a name (PEP 562)."""
    import engine

    modules = set(engine._LAZY.values()) | {f"engine.{name}" for name in engine._SUBMODULES}
    return {box_of(module) for module in modules} - {ROOT_BOX}


def box_graph() -> tuple[dict[str, set[str]], dict[str, int]]:
    """Box -> boxes it imports, and box -> number of modules in it."""
    sys.path.insert(0, str(ROOT))
    graph = grimp.build_graph(*PACKAGES, exclude_type_checking_imports=False, cache_dir=None)
    edges: dict[str, set[str]] = defaultdict(set)
    sizes: dict[str, int] = defaultdict(int)
    for module in graph.modules:
        box = box_of(module)
        sizes[box] += 1
        edges[box]  # every box is a node, importing or not
        for imported in graph.find_modules_directly_imported_by(module):
            if box_of(imported) != box:
                edges[box].add(box_of(imported))
    edges[ROOT_BOX] |= lazy_imports()
    return dict(edges), dict(sizes)


def heights(edges: dict[str, set[str]]) -> dict[str, int]:
    """Longest chain of imports below each box (0 for a box that imports no other)."""
    found: dict[str, int] = {}

    def height(box: str, path: tuple[str, ...]) -> int:
        if box in path:
            raise SystemExit(f"import circle between boxes: {' -> '.join(path + (box,))}")
        if box not in found:
            found[box] = 1 + max((height(b, path + (box,)) for b in edges[box]), default=-1)
        return found[box]

    for box in edges:
        height(box, ())
    return found


def levels(edges: dict[str, set[str]]) -> dict[str, int]:
    """Row of each box: its height; a box that imports no other one (``batch/``) is raised to
    just below its lowest importer, so that it sits next to it rather than at the bottom."""
    level = heights(edges)
    importers = {box: [a for a, targets in edges.items() if box in targets] for box in edges}
    for box in sorted(edges, key=lambda b: -level[b]):
        if importers[box] and not edges[box] and box not in ("render/", "navmesh/"):
            level[box] = max(level[box], min(level[a] for a in importers[box]) - 1)
    return level


def reachable(edges: dict[str, set[str]], start: str) -> set[str]:
    seen: set[str] = set()
    todo = list(edges[start])
    while todo:
        box = todo.pop()
        if box not in seen:
            seen.add(box)
            todo.extend(edges[box])
    return seen


def reduction(edges: dict[str, set[str]]) -> set[tuple[str, str]]:
    """The arrows no longer path implies (transitive reduction of an acyclic graph)."""
    kept = set()
    for a, targets in edges.items():
        implied = set().union(*(reachable(edges, b) for b in targets)) if targets else set()
        kept |= {(a, b) for b in targets if b not in implied}
    return kept


def row_order(rows: dict[int, list[str]], edges: dict[str, set[str]]) -> None:
    """Order each row by the mean position of the boxes it imports (a few sweeps, fewer
    crossings), ties by name."""
    position = {box: i for row in rows.values() for i, box in enumerate(sorted(row))}
    for _ in range(6):
        for level in sorted(rows):

            def key(box: str) -> tuple[float, str]:
                near = [position[b] for b in edges[box]] + [
                    position[a] for a, targets in edges.items() if box in targets
                ]
                return (sum(near) / len(near) if near else position[box], box)

            rows[level].sort(key=key)
            position.update({box: i for i, box in enumerate(rows[level])})


def draw(output: Path) -> None:
    edges, sizes = box_graph()
    lazy = lazy_imports()
    height = levels(edges)
    rows: dict[int, list[str]] = defaultdict(list)
    for box, level in height.items():
        rows[level].append(box)
    row_order(rows, edges)
    widest = max(len(row) for row in rows.values())
    width = 2.7 * widest  # a box is 2.2 wide
    xy = {}
    for level, row in rows.items():
        for i, box in enumerate(row):
            xy[box] = ((i + 0.5) * width / len(row), 1.3 * level)
    fig, ax = plt.subplots(figsize=(1.25 * width, 0.62 * 1.3 * len(rows) + 1.2), dpi=110)
    strong = reduction(edges)
    half = {box: 0.2 + 0.09 * box.count("\n") for box in xy}  # half the height of a box
    for a, targets in edges.items():
        for b in targets:
            (x0, y0), (x1, y1) = xy[a], xy[b]
            y0, y1 = y0 - half[a], y1 + half[b]
            if (a, b) in strong:
                dashed = a == ROOT_BOX and b in lazy
                ax.annotate(
                    "",
                    xy=(x1, y1),
                    xytext=(x0, y0),
                    arrowprops={
                        "arrowstyle": "-|>",
                        "color": "#1f4e79",
                        "lw": 1.3,
                        "linestyle": "--" if dashed else "-",
                    },
                    zorder=1,
                )
            else:
                ax.plot([x0, x1], [y0, y1], color="#c8c8c8", lw=0.6, zorder=0)
    for box, (x, y) in xy.items():
        library = box in ("render/", "navmesh/")
        face = box in (FACE_BOX, ROOT_BOX)
        color = "#fde9c8" if library else "#e6eef8" if face else "#dcefdc"
        ax.add_patch(
            FancyBboxPatch(
                (x - 1.1, y - half[box]),
                2.2,
                2 * half[box],
                boxstyle="round,pad=0.02",
                facecolor=color,
                edgecolor="#444444",
                zorder=2,
            )
        )
        label = box if "\n" in box or box == ROOT_BOX else f"{box} ({sizes[box]})"
        ax.text(x, y, label, ha="center", va="center", fontsize=10, zorder=3)
    ax.set_xlim(-0.2, width + 0.2)
    ax.set_ylim(-0.6, 1.3 * max(rows) + 0.6)
    ax.axis("off")
    ax.set_title(
        "rigidsim's layers, from the import graph: each arrow is an import, pointing down\n"
        "green: engine folders (module count); blue: faces; orange: leaf libraries; dashed: names"
        " engine/__init__ resolves on first use;\ngrey: imports a longer path already implies",
        fontsize=9,
    )
    fig.tight_layout()
    fig.savefig(output)
    print(f"wrote {output.relative_to(ROOT) if output.is_relative_to(ROOT) else output}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", type=Path, default=ROOT / "docs" / "architecture.png")
    draw(parser.parse_args().output.resolve())


if __name__ == "__main__":
    main()
