"""What lets unchanged Habitat code (habitat-lab) import rigidsim: the top of ``engine``.

- :mod:`engine.habitat_compat.alias`: the opt-in import alias. ``alias.install()`` makes
  ``import habitat_sim`` give :mod:`engine`, ``import magnum`` give :mod:`engine.mn` and
  ``import corrade`` give :mod:`engine.habitat_compat.corrade` (the same module objects, so
  ``habitat_sim.Simulator is engine.Simulator``). It refuses while a real Habitat-sim or
  Magnum is importable, unless forced. The separate distribution ``rigidsim-habitat-alias``
  (``scripts/habitat_alias``) calls it at interpreter start.
- the Habitat modules rigidsim has under another name, served at their Habitat paths by the
  alias: ``habitat_sim.sim`` (:mod:`engine.habitat_compat.sim`), ``habitat_sim._ext``
  (:mod:`engine.habitat_compat.ext`) and corrade's ``containers``
  (:mod:`engine.habitat_compat.corrade`).

The names of features rigidsim lacks are placeholders
(:class:`engine.core.placeholder.Placeholder`: constructing or calling one raises
``NotImplementedError`` naming what rigidsim lacks and what it offers instead) and live
where Habitat puts them: :mod:`engine.physics.objects.articulated` (articulated objects),
:mod:`engine.sensors.replay` (the replay renderer), :mod:`engine.mn.trade`,
:mod:`engine.mn.meshtools`, :mod:`engine.mn.scenetools`, :mod:`engine.mn.images` (Magnum's
importers, mesh tools and image views); ``docs/habitat_lab.md`` lists them.

May import every folder of ``engine``; nothing in ``engine`` imports this package (only
``engine.__getattr__`` resolves ``engine.sim`` and ``engine._ext`` here, by name).
"""
