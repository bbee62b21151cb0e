"""Sphinx configuration of rigidsim's documentation site (built by ``bash scripts/docs.sh``).

Why Sphinx: autodoc reads the API reference straight from the docstrings of the three packages,
myst-parser reads these Markdown pages, myst-nb renders the executed notebooks (figures and
embedded videos), and MathJax is loaded from a local copy that the ``jupyter-server-mathjax``
package (Jupyter's own MathJax bundle, on PyPI) ships: no page fetches anything from the network.
The theme is Furo (navigation sidebar and Sphinx's own offline search).
"""

from __future__ import annotations

import os
import re
import shutil
import sys
from datetime import date
from importlib.metadata import PackageNotFoundError
from importlib.metadata import version as package_version
from pathlib import Path

import jupyter_server_mathjax

HERE = Path(__file__).resolve().parent
# the checkout: docs/.. when built in place, else the folder scripts/build_docs.py names (it
# builds from a copy of docs/ laid out under build/)
ROOT = Path(os.environ.get("RIGIDSIM_DOCS_ROOT", HERE.parent)).resolve()
sys.path.insert(0, str(ROOT))

project = "rigidsim"
author = "the rigidsim authors"
copyright = f"2025-{date.today().year}, {author}"
try:
    release = package_version("rigidsim")
except PackageNotFoundError:  # a checkout that is not installed: the version pyproject.toml gives
    _PYPROJECT = (ROOT / "pyproject.toml").read_text(encoding="utf-8")
    release = re.search(r'^version = "([^"]+)"', _PYPROJECT, re.MULTILINE).group(1)
version = release

extensions = [
    "myst_nb",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
]
exclude_patterns = ["_build", "**.ipynb_checkpoints", "conf.py", "_static/mathjax/**"]
source_suffix = {".md": "myst-nb", ".ipynb": "myst-nb"}

# --- notebooks: rendered with the outputs scripts/build_docs.py put into them -----------------
nb_execution_mode = "off"
nb_merge_streams = True
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence"]
myst_heading_anchors = 3

# --- API reference from the docstrings --------------------------------------------------------
autosummary_generate = True
autosummary_ignore_module_all = False
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_typehints = "description"
autodoc_member_order = "bysource"
napoleon_numpy_docstring = True
napoleon_google_docstring = True
# every reference into rigidsim must name something (docs/api_hooks.py resolves names written
# relative to their package and leaves types outside rigidsim as plain text)
nitpicky = True


# local extensions: docs/api_hooks.py (exports listed as links, names in types resolved as
# Python resolves them, attribute comments kept as prose) and docs/search_offline.py (search
# results with text on a site opened from disk)
sys.path.insert(0, str(HERE))
extensions += ["api_hooks", "search_offline"]


# --- math with no network: MathJax 2 from the jupyter-server-mathjax package -----------------
_MATHJAX = Path(jupyter_server_mathjax.__file__).parent / "static"
_STATIC = HERE / "_static"
if not (_STATIC / "mathjax" / "MathJax.js").is_file():
    # the TeX input, HTML-CSS / SVG output and STIX-Web fonts; English only, no speech maps
    shutil.copytree(
        _MATHJAX,
        _STATIC / "mathjax",
        dirs_exist_ok=True,
        ignore=lambda folder, names: [
            name
            for name in names
            if name == "mathmaps" or (Path(folder).name == "localization" and name != "en")
        ],
    )
mathjax_path = "mathjax/MathJax.js?config=TeX-AMS-MML_HTMLorMML-full"
myst_update_mathjax = False  # its MathJax 3 settings would leave MathJax 2 idle
mathjax2_config = {
    "tex2jax": {
        "inlineMath": [["\\(", "\\)"]],
        "displayMath": [["\\[", "\\]"]],
        "processClass": "math|tex2jax_process",
    },
    "HTML-CSS": {"availableFonts": [], "webFont": "STIX-Web", "imageFont": None},
    "SVG": {"font": "STIX-Web"},
    "menuSettings": {"zoom": "None"},
    "showMathMenu": False,
}

# --- HTML -------------------------------------------------------------------------------------
html_theme = "furo"
html_title = f"rigidsim {release}"
html_static_path = ["_static"]
html_show_sourcelink = False
# ambiguous short names (a class re-exported by its package) resolve to either page: fine
suppress_warnings = ["mystnb.unknown_mime_type", "myst.header"]
