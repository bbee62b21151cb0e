#!/usr/bin/env bash
# habitat-lab on rigidsim, checked in its own virtual environment (.venv-habitat-lab, reused
# when present): habitat-lab 0.3.320260507 with its pins (numpy 1.26.4, gym 0.23, numba,
# opencv, hydra), rigidsim (editable) and the rigidsim-habitat-alias start-up hook; then
# rigidsim's alias, placeholder, Magnum-math and rasterizer tests under that numpy, and
# scripts/habitat_lab_check.py
# (import habitat, PointNav with the oracle follower, metrics, gym, VectorEnv, ImageNav).
# A few minutes with a warm pip cache. Usage: bash scripts/habitat_lab_check.sh; scripts/test.sh
# runs it in two halves, --dependencies-only in the background and then --dependencies-ready.
set -euo pipefail
cd "$(dirname "$0")/.."
venv=.venv-habitat-lab
start=$SECONDS
case "${1:-}" in
  "" | --dependencies-only | --dependencies-ready) ;;
  *) echo "usage: bash scripts/habitat_lab_check.sh [--dependencies-only | --dependencies-ready]" >&2; exit 2 ;;
esac
if [ "${1:-}" != --dependencies-ready ]; then
  # habitat-lab, rigidsim's own dependencies (resolved together: habitat-lab pins numpy), the
  # alias and the test runner; rigidsim itself below, so that this can run beside another
  # environment's install (scripts/test.sh): the editable install writes into the checkout
  [ -x "$venv/bin/python" ] || python3 -m venv "$venv"
  requirements=$(mktemp)
  python3 scripts/requirements.py >"$requirements"
  "$venv/bin/python" -m pip install -q --disable-pip-version-check --no-compile \
    "habitat-lab==0.3.320260507" -r "$requirements" ./scripts/habitat_alias "pytest>=7.4" "hypothesis>=6.80"
  rm -f "$requirements"
  [ "${1:-}" != --dependencies-only ] || exit 0
fi
"$venv/bin/python" -m pip install -q --disable-pip-version-check --no-deps -e .
echo "habitat_lab_check.sh: environment ready in $((SECONDS - start)) s"
# rigidsim itself under habitat-lab's numpy; pytest's own summary goes to a log so that this
# script's output ends with the habitat-lab check's line, not a second test count
log=$(mktemp)
basetemp=$(mktemp -d)  # its own: scripts/test.sh runs this beside the main suite's pytest
if ! "$venv/bin/python" -m pytest -q -p no:cacheprovider --basetemp "$basetemp" \
  tests/engine/test_habitat_alias.py tests/engine/test_habitat_names.py \
  tests/engine/test_mn.py tests/engine/test_mn_parity.py tests/render/test_raster.py >"$log" 2>&1; then
  cat "$log"; rm -rf "$log" "$basetemp"; exit 1
fi
rm -rf "$log" "$basetemp"
echo "habitat_lab_check.sh: rigidsim's tests pass under numpy $("$venv/bin/python" -c 'import numpy; print(numpy.__version__)')"
"$venv/bin/python" scripts/habitat_lab_check.py
echo "habitat_lab_check.sh: done in $((SECONDS - start)) s"
