#!/usr/bin/env bash
# Build the documentation site into build/docs/ (open build/docs/index.html): the pages of
# docs/, every notebook of notebooks/ executed with its figures and videos, and the API
# reference from the docstrings; math is typeset offline (scripts/build_docs.py says how).
#
#   bash scripts/docs.sh                  # full-size notebooks (about 10 min on 2 cores)
#   bash scripts/docs.sh --fast           # the notebooks' fast mode (about 4 min)
#   bash scripts/docs.sh --executed DIR   # reuse notebooks already executed in DIR
#   bash scripts/docs.sh --out DIR        # another output folder
#   bash scripts/docs.sh --jobs 1         # Sphinx in one process (default: one per core)
#
# It installs what it needs into ./.venv (created where missing) every time, so it works
# after scripts/test.sh or scripts/tutorial.sh made the venv with other extras. With PYTHON
# set, that interpreter is used as it is (its environment must have the docs extra).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ -z "${PYTHON:-}" ]; then
    if [ ! -x .venv/bin/python ]; then
        python3 -m venv .venv
        .venv/bin/python -m pip install -q --upgrade pip
    fi
    .venv/bin/python -m pip install -q -e '.[docs,notebook,gym,ray,viewer]'
    PYTHON=.venv/bin/python
fi
out=build/docs
args=("$@")
for ((i = 0; i < ${#args[@]}; i++)); do
    if [ "${args[$i]}" = "--out" ]; then out="${args[$((i + 1))]}"; fi
done
"$PYTHON" scripts/build_docs.py "$@"
# the 3D viewer's replay of the tutorial, embedded by docs/viewer.md
mkdir -p "$out/replays"
"$PYTHON" -m engine.viewer --demo-replay "$out/replays/tutorial_replay.html"
echo "open $out/index.html"
