#!/usr/bin/env bash
# Build the documentation's executed notebooks: every notebook in notebooks/ is run top to
# bottom with nbconvert and written as HTML, figures and videos embedded, to build/docs/
# (gitignored; open build/docs/index.html). The notebooks in the repository stay without
# outputs. Options: RIGIDSIM_FAST=1 bash scripts/docs.sh builds small, quick versions.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ -z "${PYTHON:-}" ]; then
    if [ ! -x .venv/bin/python ]; then
        python3 -m venv .venv
        .venv/bin/python -m pip install -q --upgrade pip
        .venv/bin/python -m pip install -q -e '.[notebook]'
    fi
    PYTHON=.venv/bin/python
fi
out=build/docs
rm -rf "$out"
mkdir -p "$out/run"
cp notebooks/*.ipynb "$out/run/"  # executed in a scratch copy: videos and files land there
export PYTHONPATH="$PWD${PYTHONPATH:+:$PYTHONPATH}" MPLBACKEND=module://matplotlib_inline.backend_inline
index="$out/index.html"
echo "<html><head><title>rigidsim notebooks</title></head><body><h1>rigidsim notebooks</h1><ul>" > "$index"
for notebook in "$out"/run/*.ipynb; do
    name=$(basename "$notebook" .ipynb)
    echo "executing $name"
    "$PYTHON" -m jupyter nbconvert --to html --execute --ExecutePreprocessor.timeout=1800 \
        --output-dir "$out" --output "$name" "$notebook"
    echo "<li><a href=\"$name.html\">$name</a></li>" >> "$index"
done
echo "</ul></body></html>" >> "$index"
rm -rf "$out/run"
echo "wrote $index"
