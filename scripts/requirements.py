"""Print rigidsim's requirements from ``pyproject.toml``, one per line, for ``pip install -r``.

``python scripts/requirements.py notebook`` prints the core dependencies and the ``notebook``
extra's; several extras may be named; ``--extras-only`` leaves the core dependencies out.
``scripts/test.sh`` uses it to install the dependencies of its three environments at the same
time: each ``pip install -r`` touches only its own environment, while the editable installs of
rigidsim itself (which write the build metadata into the source folder) then run one after the
other with ``--no-deps``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10: pip vendors the same parser
    from pip._vendor import tomli as tomllib

PYPROJECT = Path(__file__).resolve().parent.parent / "pyproject.toml"


def requirements(extras: list[str], core: bool = True) -> list[str]:
    """The core dependencies (unless ``core`` is false) and those of ``extras``, in order,
    each once; an extra that pyproject.toml does not define raises ``KeyError`` naming it."""
    project = tomllib.loads(PYPROJECT.read_text(encoding="utf-8"))["project"]
    optional = project["optional-dependencies"]
    unknown = [extra for extra in extras if extra not in optional]
    if unknown:
        raise KeyError(f"no extra {unknown} in pyproject.toml; extras: {sorted(optional)}")
    listed = list(project["dependencies"]) if core else []
    for extra in extras:
        listed += optional[extra]
    return list(dict.fromkeys(listed))


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("extras", nargs="*", help="extras of pyproject.toml to include")
    parser.add_argument("--extras-only", action="store_true", help="leave out core dependencies")
    args = parser.parse_args(argv)
    try:
        listed = requirements(args.extras, core=not args.extras_only)
    except KeyError as error:
        parser.error(str(error.args[0]))
    print("\n".join(listed))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
