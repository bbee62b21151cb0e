#!/usr/bin/env bash
# Install rigidsim into ./.venv and run Habitat's rigid-object tutorial end to end on the
# bundled demo scene, writing its nine videos to ./tutorial_output (extra args are passed on).
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -m venv .venv
.venv/bin/python -m pip install -q --upgrade pip
.venv/bin/python -m pip install -q -e .
.venv/bin/python -m engine.tutorial "$@"
