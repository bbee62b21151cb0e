"""Build rigidsim's documentation site with Sphinx: pages, executed notebooks, API reference.

``bash scripts/docs.sh`` installs what this needs and calls it; the browser test calls it too.
Steps:

1. lay out a source tree in ``<out>-src/``: every file of ``docs/`` and, under ``notebooks/``,
   every notebook of ``notebooks/`` with its outputs;
2. the outputs come from running the notebook top to bottom (nbclient, a fresh kernel of this
   interpreter, in a scratch folder), or from an already executed copy given with
   ``--executed DIR`` (the test suite's notebook test leaves one there, so CI runs each notebook
   once); absolute paths of the scratch folder and of the repository are removed from outputs;
3. the measurement reports that pages link (``../benchmarks/results/<name>.md``) become pages
   of the site;
4. ``sphinx-build`` writes the HTML site to ``<out>/`` (default ``build/docs/``), MathJax
   copied from the ``jupyter-server-mathjax`` package so that equations render with no network.
   Warnings are errors (``-W --keep-going``: all of them are listed, then the build fails), so
   the site never builds with a malformed docstring, a dead link or an object described twice;
   ``tests/notebooks/test_site.py`` also fails on any ``WARNING``/``ERROR`` line of the
   build's output (a notebook kernel's included).
"""

from __future__ import annotations

import argparse
import logging
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import nbformat
from nbclient import NotebookClient
from tqdm import tqdm
from traitlets.config import Config

LOG = logging.getLogger("rigidsim.docs")
ROOT = Path(__file__).resolve().parents[1]
CELL_TIMEOUT_S = 1800


def sources_match(executed: nbformat.NotebookNode, source: nbformat.NotebookNode) -> bool:
    """True when ``executed`` ran exactly the cells of ``source`` (an edited notebook re-runs)."""
    cells = [(cell.cell_type, cell.source) for cell in source.cells]
    return cells == [(cell.cell_type, cell.source) for cell in executed.cells]


def scrub_paths(notebook: nbformat.NotebookNode, folders: list[str]) -> None:
    """Replace the absolute ``folders`` in text outputs: a page must not show the build machine."""
    folders = sorted({f.rstrip("/") for f in folders if f}, key=len, reverse=True)

    def clean(text: str) -> str:
        for folder in folders:
            text = text.replace(folder + "/", "").replace(folder, ".")
        return text

    for cell in notebook.cells:
        for output in cell.get("outputs", []):
            if "text" in output:
                output["text"] = clean(output["text"])
            for mime in ("text/plain", "text/html", "text/markdown"):
                data = output.get("data", {})
                if mime in data:
                    value = data[mime]
                    data[mime] = (
                        [clean(v) for v in value] if isinstance(value, list) else clean(value)
                    )


WIDGET_MIME = "application/vnd.jupyter.widget-view+json"


def drop_widgets(notebook: nbformat.NotebookNode) -> None:
    """Remove Jupyter widget outputs and state (tqdm's bars in a notebook).

    A page showing them would load the widget manager from a CDN; the text of a finished bar
    says nothing a reader needs, and its state holds the scratch folder's absolute paths.
    """
    notebook.metadata.pop("widgets", None)
    for cell in notebook.cells:
        if "outputs" in cell:
            cell["outputs"] = [o for o in cell["outputs"] if WIDGET_MIME not in o.get("data", {})]


def execute_notebook(path: Path, fast: bool) -> nbformat.NotebookNode:
    """Run ``path`` top to bottom in a scratch folder and return it with outputs."""
    notebook = nbformat.read(path, as_version=4)
    env_before = dict(os.environ)
    os.environ["PYTHONPATH"] = os.pathsep.join(
        filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])
    )
    os.environ["MPLBACKEND"] = "module://matplotlib_inline.backend_inline"
    if fast:
        os.environ["RIGIDSIM_FAST"] = "1"
    try:
        with tempfile.TemporaryDirectory(prefix="rigidsim-docs-") as scratch:
            # the kernel talks over local sockets (IPC) in the scratch folder: over TCP
            # without encryption keys, every kernel would log a warning into the build's output
            sockets = os.path.join(scratch, "kernel-ipc")  # absolute: the kernel runs elsewhere
            client = NotebookClient(
                notebook,
                config=Config({"KernelManager": {"transport": "ipc", "ip": sockets}}),
                timeout=CELL_TIMEOUT_S,
                kernel_name="python3",
                resources={"metadata": {"path": scratch}},
            )
            client.execute()
            scrub_paths(notebook, [scratch, os.path.realpath(scratch)])
    finally:
        os.environ.clear()
        os.environ.update(env_before)
    return notebook


REPORT_LINK = re.compile(r"\]\(\.\./benchmarks/results/([\w.-]+\.md)\)")


def add_linked_reports(src: Path) -> None:
    """Give every measurement report a page links to a page of its own in the site.

    A page of ``docs/`` links a report as ``../benchmarks/results/<name>.md`` (the path that
    works when the page is read in the repository); in the site the report becomes the page
    ``reports/<name>``, the link points to it, and a "Measurement reports" table of contents
    lists the reports.
    """
    names: set[str] = set()
    for page in sorted(src.glob("*.md")):
        text = page.read_text(encoding="utf-8")
        names |= set(REPORT_LINK.findall(text))
        linked = REPORT_LINK.sub(lambda match: f"](reports/{match.group(1)})", text)
        if linked != text:
            page.write_text(linked, encoding="utf-8")
    if not names:
        return
    (src / "reports").mkdir()
    for name in sorted(names):
        shutil.copy2(ROOT / "benchmarks" / "results" / name, src / "reports" / name)
    toc = ["", "```{toctree}", ":caption: Measurement reports", ":maxdepth: 1", ":glob:", ""]
    with (src / "index.md").open("a", encoding="utf-8") as index:
        index.write("\n".join([*toc, "reports/*", "```", ""]))


def lay_out_sources(src: Path, executed_dir: Path | None, fast: bool) -> None:
    """Fill ``src`` with the docs pages, the reports they link and the executed notebooks."""
    if src.exists():
        shutil.rmtree(src)
    shutil.copytree(ROOT / "docs", src)
    add_linked_reports(src)
    (src / "notebooks").mkdir()
    notebooks = sorted((ROOT / "notebooks").glob("*.ipynb"))
    home = str(Path.home())
    for path in tqdm(notebooks, desc="docs: notebooks", unit="notebook"):
        source = nbformat.read(path, as_version=4)
        cached = executed_dir / path.name if executed_dir is not None else None
        if cached is not None and cached.is_file():
            notebook = nbformat.read(cached, as_version=4)
            if not sources_match(notebook, source):
                LOG.info("%s: executed copy is stale, running it", path.name)
                notebook = execute_notebook(path, fast)
            else:
                LOG.info("%s: reusing the executed copy in %s", path.name, executed_dir)
        else:
            tqdm.write(f"docs: executing {path.name}")
            notebook = execute_notebook(path, fast)
        drop_widgets(notebook)
        scratch = str(notebook.metadata.pop("rigidsim_scratch", ""))  # the test's tmp folder
        scrub_paths(notebook, [scratch, str(ROOT), os.path.realpath(ROOT), home])
        nbformat.write(notebook, src / "notebooks" / path.name)


def scrub_site(out: Path, folders: list[str]) -> None:
    """Remove absolute folders from the written pages (autodoc prints the values of module
    constants, and a module object's repr holds its file's absolute path)."""
    folders = sorted({f.rstrip("/") for f in folders if f}, key=len, reverse=True)
    for path in [*out.rglob("*.html"), out / "searchindex.js", out / "_static" / "search_pages.js"]:
        if not path.is_file():
            continue
        text = path.read_text(encoding="utf-8")
        cleaned = text
        for folder in folders:
            cleaned = cleaned.replace(folder + "/", "").replace(folder, ".")
        if cleaned != text:
            path.write_text(cleaned, encoding="utf-8")


def package_modules() -> dict[str, list[str]]:
    """Every module of ``engine``, ``render`` and ``navmesh`` by package, found by file name.

    Nothing is imported here (``engine.tutorial.__main__`` runs the main job when imported, so
    ``__main__`` modules are left out); autodoc imports each listed module when it renders it.
    """
    packages: dict[str, list[str]] = {}
    for top in ("engine", "render", "navmesh"):
        for init in sorted((ROOT / top).rglob("__init__.py")):
            package = ".".join(init.parent.relative_to(ROOT).parts)
            modules = [package] + [
                f"{package}.{path.stem}"
                for path in sorted(init.parent.glob("*.py"))
                if path.stem not in ("__init__", "__main__")
            ]
            packages[package] = modules
    return packages


# Each object is described once, in the section of the module that defines it: a package's
# ``__all__`` re-exports names of its modules, which autodoc would otherwise describe again
# (three ``apply_impulse`` in the search); docs/conf.py lists a module's exports as links.
AUTOMODULE_OPTIONS = ["   :members:", "   :ignore-module-all:"]


def write_api_pages(src: Path) -> None:
    """One API page per package, one section per module, rendered by autodoc from docstrings."""
    api = src / "api"
    api.mkdir()
    for package, modules in package_modules().items():
        lines = [f"# `{package}`", ""]
        for module in modules:
            if module != package:
                lines += [f"## `{module}`", ""]
            lines += ["```{eval-rst}", f".. automodule:: {module}", *AUTOMODULE_OPTIONS, "```", ""]
        (api / f"{package}.md").write_text("\n".join(lines), encoding="utf-8")


# warnings are errors (every one reported before the build fails); Sphinx's processes: --jobs
SPHINX_STRICT = ["-W", "--keep-going"]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT / "build" / "docs", help="site folder")
    parser.add_argument("--fast", action="store_true", help="notebooks in RIGIDSIM_FAST mode")
    parser.add_argument(
        "--executed", type=Path, default=None, help="folder of already executed notebooks to reuse"
    )
    parser.add_argument(
        "--jobs",
        default="auto",
        help="Sphinx's processes (default auto: one per core); the test suite, whose other "
        "workers keep the cores busy, builds with 1, which spends about a fifth less CPU",
    )
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    fast = args.fast or os.environ.get("RIGIDSIM_FAST") == "1"
    out = args.out.resolve()
    src = out.with_name(out.name + "-src")
    doctrees = out.with_name(out.name + "-doctrees")  # Sphinx's cache, outside the site
    start = time.perf_counter()
    lay_out_sources(src, args.executed, fast)
    write_api_pages(src)
    notebooks_s = time.perf_counter() - start
    if out.exists():
        shutil.rmtree(out)
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    env["RIGIDSIM_DOCS_ROOT"] = str(ROOT)  # docs/conf.py reads the version from its pyproject
    LOG.info("docs: sphinx-build %s -> %s", src.name, out)
    sphinx = subprocess.run(
        [
            sys.executable,
            "-m",
            "sphinx",
            "-b",
            "html",
            "-q",
            *SPHINX_STRICT,
            "-j",
            str(args.jobs),
            "-d",
            str(doctrees),
            str(src),
            str(out),
        ],
        env=env,
        cwd=ROOT,
    )
    if sphinx.returncode != 0:
        LOG.error("docs: Sphinx failed: every warning above is an error (-W); fix them")
        return sphinx.returncode
    scrub_site(out, [str(ROOT), os.path.realpath(ROOT), str(Path.home())])
    total_s = time.perf_counter() - start
    LOG.info(
        "docs: wrote %s in %.0f s (notebooks %.0f s, Sphinx %.0f s)",
        out / "index.html",
        total_s,
        notebooks_s,
        total_s - notebooks_s,
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
