#!/usr/bin/env bash
# The test command. It creates (where missing) and fills three environments: ./.venv with
# rigidsim and its test extras, ./.venv-notebook with the notebook extra alone (the notebooks
# execute there) and ./.venv-habitat-lab with habitat-lab's pins; then it runs ruff, ruff
# format, mypy, the import contracts, the test suite on every core (pytest-xdist) and the
# habitat-lab check, and prints how long each part took. The dependencies of the second and
# third environments install in the background while the first is filled and checked (each pip
# writes only into its own environment); rigidsim's editable installs, which write build
# metadata into this folder, run one after the other. It installs nothing system-wide: the
# browser tests use a Chromium that is already there, or skip with a message (.ci/run installs
# one for CI). Extra args go to pytest.
set -euo pipefail
cd "$(dirname "$0")/.."
trap 'kill $(jobs -p) 2>/dev/null || true; echo "scripts/test.sh: $((SECONDS / 60)) min $((SECONDS % 60)) s"' EXIT
say() { echo "scripts/test.sh: $* at $((SECONDS / 60)) min $((SECONDS % 60)) s"; }
logs=$(mktemp -d)

# waits for a background install; on failure shows its log and stops
await() {
  local pid=$1 what=$2 log=$3
  if ! wait "$pid"; then
    cat "$log" >&2
    echo "scripts/test.sh: installing $what failed (log above)" >&2
    exit 1
  fi
  say "$what ready"
}

python3 scripts/requirements.py notebook >"$logs/notebook.txt"
{
  [ -x .venv-notebook/bin/python ] || python3 -m venv .venv-notebook
  .venv-notebook/bin/python -m pip install -q -r "$logs/notebook.txt"
} >"$logs/notebook.log" 2>&1 &
notebook_deps=$!
bash scripts/habitat_lab_check.sh --dependencies-only >"$logs/habitat.log" 2>&1 &
habitat_deps=$!

[ -x .venv/bin/python ] || python3 -m venv .venv
.venv/bin/python -m pip install -q -e '.[dev,notebook,ray,gym,viewer,docs]'
say "the test environment ready"
.venv/bin/python -m ruff check engine render navmesh tests benchmarks examples scripts docs/conf.py
.venv/bin/python -m ruff format --check engine render navmesh tests benchmarks examples scripts docs/conf.py
.venv/bin/python -m mypy  # configured in pyproject.toml ([tool.mypy])
.venv/bin/lint-imports  # import contracts, configured in pyproject.toml ([tool.importlinter])
say "lint, types and import contracts clean"

# the notebooks execute in a kernel of this environment (docs/testing.md)
await "$notebook_deps" "the notebooks' environment" "$logs/notebook.log"
.venv-notebook/bin/python -m pip install -q --no-deps -e .
export RIGIDSIM_NOTEBOOK_PYTHON="$PWD/.venv-notebook/bin/python"
.venv/bin/python -m pytest -q -n auto --dist loadfile "$@"
say "pytest done"

await "$habitat_deps" "habitat-lab's environment" "$logs/habitat.log"
bash scripts/habitat_lab_check.sh --dependencies-ready  # habitat-lab on rigidsim (.venv-habitat-lab)
rm -rf "$logs"
