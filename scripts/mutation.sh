#!/usr/bin/env bash
# Mutation testing of the physics, rasterizer and navigation kernels (on demand, NEVER in CI).
#
#   bash scripts/mutation.sh                          # all modules, 60 sampled mutants each
#   bash scripts/mutation.sh navmesh/step_filter.py   # one module
#   bash scripts/mutation.sh --per-module 20 render/camera.py
#
# Needs the `mutation` extra (cosmic-ray): pip install -e '.[dev,mutation]'.
# cosmic-ray mutates a temporary copy of the repository, never this checkout. Prints each
# module's score (killed / non-equivalent mutants, target >= 90 %) and writes the report
# benchmarks/results/mutation-<date>.md. How to read it: docs/testing.md.
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON="${PYTHON:-$( [ -x .venv/bin/python ] && echo .venv/bin/python || echo python3 )}"
PYTHON="$(cd "$(dirname "$PYTHON")" && pwd)/$(basename "$PYTHON")"
exec "$PYTHON" scripts/mutation.py "$@"
