"""The generated demo content: a Habitat-like ``data`` folder built from code, on first use.

``demo_data_path()`` (:mod:`engine.demo.datasets`) returns the folder (cached in
``~/.cache/rigidsim``, or ``RIGIDSIM_DATA_DIR``); :mod:`engine.demo.scene` builds the
apartment stage, :mod:`engine.demo.objects` the example objects, :mod:`engine.demo.geometry`
the mesh and glTF helpers they share. The Habitat-mirroring API (``engine``) never needs
this package; the tutorial, notebooks and tests do.

May import: ``engine.scene`` (assets, primitives) and ``navmesh`` (the apartment's
navmesh); never the simulator. Read :mod:`~engine.demo.geometry` first, then
:mod:`~engine.demo.scene`, :mod:`~engine.demo.objects`, :mod:`~engine.demo.datasets`.
"""

from __future__ import annotations

from engine.demo.datasets import demo_data_path

__all__ = ["demo_data_path"]
