#!/usr/bin/env bash
# The test command. It creates (where missing) and fills three environments: ./.venv with
# rigidsim and its test extras, ./.venv-notebook with the notebook extra alone (the notebooks
# execute there) and ./.venv-habitat-lab with habitat-lab's pins; then it runs the test suite on
# every core (pytest-xdist) and, beside it, ruff, ruff format, mypy, the import contracts and
# the habitat-lab check, and prints how long each part took. The dependencies of the second
# and third environments install in the background while the first is filled (each pip writes
# only into its own environment); rigidsim's editable installs, which write build metadata into
# this folder, run one after the other (the habitat-lab one waits for a marker file that the
# other two leave). The installs skip compiling every file they install to bytecode (pip
# --no-compile, about a third of their time); Python compiles what is imported, once, into one
# folder (PYTHONPYCACHEPREFIX=.cache/pycache), written even where PYTHONDONTWRITEBYTECODE is set
# (without it, each of the suite's processes would compile its imports again). It installs
# nothing system-wide: the browser tests use a Chromium that is already there, or skip with a
# message (.ci/run installs one for CI). Extra args go to pytest.
set -euo pipefail
cd "$(dirname "$0")/.."
trap 'kill $(jobs -p) 2>/dev/null || true; echo "scripts/test.sh: $((SECONDS / 60)) min $((SECONDS % 60)) s"' EXIT
say() { echo "scripts/test.sh: $* at $((SECONDS / 60)) min $((SECONDS % 60)) s"; }
logs=$(mktemp -d)
unset PYTHONDONTWRITEBYTECODE
export PYTHONPYCACHEPREFIX="$PWD/.cache/pycache"

# waits for a background job; shows its log when it failed, or always with a 4th argument
await() {
  local pid=$1 what=$2 log=$3 show=${4:-} status=0
  wait "$pid" || status=$?
  if [ "$status" != 0 ] || [ -n "$show" ]; then cat "$log"; fi
  if [ "$status" != 0 ]; then
    echo "scripts/test.sh: $what failed (log above)" >&2
    exit 1
  fi
  say "$what done"
}

python3 scripts/requirements.py notebook >"$logs/notebook.txt"
{
  [ -x .venv-notebook/bin/python ] || python3 -m venv .venv-notebook
  .venv-notebook/bin/python -m pip install -q --no-compile -r "$logs/notebook.txt"
} >"$logs/notebook.log" 2>&1 &
notebook_deps=$!
# habitat-lab's environment, then (once rigidsim's other editable installs are done) its check
{
  if ! bash scripts/habitat_lab_check.sh --dependencies-only >"$logs/habitat_deps.log" 2>&1; then
    cat "$logs/habitat_deps.log"
    echo "installing habitat-lab's environment failed"
    exit 1
  fi
  until [ -e "$logs/editable-installs-done" ]; do sleep 1; done
  bash scripts/habitat_lab_check.sh --dependencies-ready
} >"$logs/habitat.log" 2>&1 &
habitat_check=$!

[ -x .venv/bin/python ] || python3 -m venv .venv
.venv/bin/python -m pip install -q --no-compile -e '.[dev,notebook,ray,gym,viewer,docs]'
say "the test environment ready"
# lint, types and import contracts: one process, beside pytest
{
  .venv/bin/python -m ruff check engine render navmesh tests benchmarks examples scripts docs/conf.py
  .venv/bin/python -m ruff format --check engine render navmesh tests benchmarks examples scripts docs/conf.py
  .venv/bin/python -m mypy # configured in pyproject.toml ([tool.mypy])
  .venv/bin/lint-imports   # import contracts, configured in pyproject.toml ([tool.importlinter])
} >"$logs/lint.log" 2>&1 &
lint=$!

# the notebooks execute in a kernel of this environment (docs/testing.md)
await "$notebook_deps" "installing the notebooks' environment" "$logs/notebook.log"
.venv-notebook/bin/python -m pip install -q --no-deps -e .
touch "$logs/editable-installs-done"
export RIGIDSIM_NOTEBOOK_PYTHON="$PWD/.venv-notebook/bin/python"
.venv/bin/python -m pytest -q -n auto --dist loadfile "$@"
say "pytest done"
await "$lint" "lint, types and import contracts" "$logs/lint.log" show
await "$habitat_check" "the habitat-lab check" "$logs/habitat.log" show
rm -rf "$logs"
