#!/usr/bin/env bash
# Mutation testing of the physics, rasterizer and navigation kernels (on demand, NEVER in CI).
#
#   bash scripts/mutation.sh                          # all 16 kernels (60 sampled mutants, 30 in one)
#   bash scripts/mutation.sh navmesh/step_filter.py   # one module
#   bash scripts/mutation.sh --per-module 20 render/camera.py   # --list: print the sample only
#
# Needs the `mutation` extra (cosmic-ray): .venv/bin/python -m pip install -e '.[dev,mutation]'.
# Uses .venv/bin/python (as scripts/test.sh); PYTHON=/path/to/python overrides it.
# cosmic-ray mutates a temporary copy of the repository, never this checkout. Prints each
# module's score (killed / non-equivalent mutants, target >= 90 %) and writes the report
# benchmarks/results/mutation-<date>.md. How to read it: docs/testing.md.
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON="${PYTHON:-$( [ -x .venv/bin/python ] && echo .venv/bin/python || echo python3 )}"
PYTHON="$(cd "$(dirname "$PYTHON")" && pwd)/$(basename "$PYTHON")"
exec "$PYTHON" scripts/mutation.py "$@"
