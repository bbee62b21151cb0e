#!/usr/bin/env bash
# The test command: installs rigidsim with its test extras into ./.venv and the notebooks'
# environment ./.venv-notebook (the notebook extra alone; both created where missing), then runs
# ruff, ruff format, mypy, the import contracts, the test suite on every core (pytest-xdist) and
# the habitat-lab check, and prints how long it took. It installs nothing system-wide: the browser tests use a Chromium that is already
# there, or skip with a message (.ci/run installs one for CI). Extra args go to pytest.
set -euo pipefail
cd "$(dirname "$0")/.."
trap 'echo "scripts/test.sh: $((SECONDS / 60)) min $((SECONDS % 60)) s"' EXIT
[ -x .venv/bin/python ] || python3 -m venv .venv
.venv/bin/python -m pip install -q --upgrade pip
.venv/bin/python -m pip install -q -e '.[dev,notebook,ray,gym,viewer,docs]'
# the notebooks execute in a kernel of this environment (docs/testing.md)
[ -x .venv-notebook/bin/python ] || python3 -m venv .venv-notebook
.venv-notebook/bin/python -m pip install -q -e '.[notebook]'
export RIGIDSIM_NOTEBOOK_PYTHON="$PWD/.venv-notebook/bin/python"
.venv/bin/python -m ruff check engine render navmesh tests benchmarks examples scripts docs/conf.py
.venv/bin/python -m ruff format --check engine render navmesh tests benchmarks examples scripts docs/conf.py
.venv/bin/python -m mypy  # configured in pyproject.toml ([tool.mypy])
.venv/bin/lint-imports  # import contracts, configured in pyproject.toml ([tool.importlinter])
.venv/bin/python -m pytest -q -n auto --dist loadfile "$@"
bash scripts/habitat_lab_check.sh  # habitat-lab on rigidsim, in its own venv (.venv-habitat-lab)
