#!/usr/bin/env bash
# Install rigidsim with its test extras into ./.venv and run the test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -m venv .venv
.venv/bin/python -m pip install -q --upgrade pip
.venv/bin/python -m pip install -q -e '.[dev,notebook,ray,gym]'
.venv/bin/python -m ruff check engine render navmesh tests benchmarks
.venv/bin/python -m ruff format --check engine render navmesh tests benchmarks
.venv/bin/python -m mypy  # configured in pyproject.toml ([tool.mypy])
.venv/bin/python -m pytest -q "$@"
