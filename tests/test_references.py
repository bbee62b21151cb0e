"""Every file the repository points a reader to is in the repository.

Design notes that never shipped with the code were once cited in docstrings, tests and
notebooks; a reader could not open them. Their content lives in ``docs/`` now, and this test
fails if a tracked file cites one of them again, or if a README link points nowhere.
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# spelled in pieces so that this file does not cite them itself
MISSING = [stem + ".md" for stem in ("DEVELOPERS", "HABITAT_SEMANTICS", "VALIDATION", "STYLE")]
MISSING.append("PERFORMANCE" + ".md")
TEXT_SUFFIXES = {".py", ".md", ".ipynb", ".toml", ".sh", ".txt", ".json", ".cfg", ".yml", ".yaml"}


def tracked_files() -> list[Path]:
    """The repository's files: git's list where there is a checkout, else the tree."""
    try:
        listed = subprocess.run(
            ["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True
        ).stdout.split("\n")
        return [ROOT / name for name in listed if name]
    except (OSError, subprocess.CalledProcessError):
        skip = {".git", ".venv", ".venv-notebook", ".venv-habitat-lab", "build", "__pycache__"}
        skip |= {".pytest_cache", ".ruff_cache"}
        return [p for p in ROOT.rglob("*") if p.is_file() and not skip & set(p.parts)]


def test_no_file_cites_a_document_that_is_not_in_the_repository() -> None:
    citing = []
    for path in tracked_files():
        if path.suffix not in TEXT_SUFFIXES and path.name not in ("run", "LICENSE"):
            continue
        if not path.is_file():
            continue
        text = path.read_text(encoding="utf-8", errors="replace")
        for name in MISSING:
            if name in text and not (ROOT / name).exists():
                citing.append(f"{path.relative_to(ROOT)}: {name}")
    assert citing == [], "cited but not in the repository:\n" + "\n".join(citing)


def test_readme_links_point_to_files_in_the_repository() -> None:
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    targets = re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", readme)
    local = [t for t in targets if "://" not in t]
    assert local, "the README links no file"
    missing = [t for t in local if not (ROOT / t).exists()]
    assert missing == [], f"README links to missing files: {missing}"
