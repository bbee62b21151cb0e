"""``habitat_sim._ext``: the package of Habitat-sim's compiled extension.

Habitat code sometimes imports a class from the extension module itself
(``from habitat_sim._ext.habitat_sim_bindings import Configuration``). rigidsim has no
extension; its :mod:`engine.bindings` already re-exports every such class (the same objects),
so the import alias maps ``habitat_sim._ext.habitat_sim_bindings`` to :mod:`engine.bindings`
and this package only holds that name.
"""

from __future__ import annotations

from engine import bindings as habitat_sim_bindings

__all__ = ["habitat_sim_bindings"]
