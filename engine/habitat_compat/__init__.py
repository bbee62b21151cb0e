"""What lets unchanged Habitat code (habitat-lab) import and run on rigidsim.

- :mod:`engine.habitat_compat.alias`: the opt-in import alias. ``alias.install()`` makes
  ``import habitat_sim`` give :mod:`engine`, ``import magnum`` give :mod:`engine.mn` and
  ``import corrade`` give :mod:`engine.habitat_compat.corrade` (the same module objects, so
  ``habitat_sim.Simulator is engine.Simulator``). It refuses while a real Habitat-sim or
  Magnum is importable, unless forced. The separate distribution ``rigidsim-habitat-alias``
  (``scripts/habitat_alias``) calls it at interpreter start.
- :mod:`engine.habitat_compat.placeholder`: the base of the names that exist only so Habitat
  code imports and annotates with them (articulated objects, the replay renderer, Magnum's
  importers): constructing or calling one raises ``NotImplementedError`` naming what rigidsim
  lacks and what it offers instead. ``docs/habitat_lab.md`` lists them.
- the Habitat modules rigidsim keeps elsewhere or lacks: ``habitat_sim.sim``
  (:mod:`engine.habitat_compat.sim`), ``habitat_sim._ext`` (:mod:`engine.habitat_compat.ext`),
  corrade's ``containers`` (:mod:`engine.habitat_compat.corrade`), the articulated-object
  names of ``habitat_sim.physics`` (:mod:`engine.habitat_compat.articulated`) and the replay
  renderer (:mod:`engine.habitat_compat.replay`).

This package's ``__init__`` imports nothing, so that the physics and math modules can take
the placeholder base from it without loading the rest.
"""
