#!/usr/bin/env bash
# Install rigidsim with its test extras into ./.venv and run the test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
# headless Chromium for the page tests (docs site, viewer): Debian's package, where it is missing
# and this user may install it; the tests skip with a message where no browser can be had
if ! command -v chromium >/dev/null 2>&1 && command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
  (apt-get install -y -q chromium >/dev/null 2>&1 \
    || (apt-get update -q >/dev/null 2>&1 && apt-get install -y -q chromium >/dev/null 2>&1)) \
    || echo "scripts/test.sh: could not install chromium; page tests will be skipped"
fi
python3 -m venv .venv
.venv/bin/python -m pip install -q --upgrade pip
.venv/bin/python -m pip install -q -e '.[dev,notebook,ray,gym,viewer,docs]'
.venv/bin/python -m ruff check engine render navmesh tests benchmarks examples scripts docs/conf.py
.venv/bin/python -m ruff format --check engine render navmesh tests benchmarks examples scripts docs/conf.py
.venv/bin/python -m mypy  # configured in pyproject.toml ([tool.mypy])
.venv/bin/lint-imports  # import contracts, configured in pyproject.toml ([tool.importlinter])
.venv/bin/python -m pytest -q "$@"
bash scripts/habitat_lab_check.sh  # habitat-lab on rigidsim, in its own venv (.venv-habitat-lab)
