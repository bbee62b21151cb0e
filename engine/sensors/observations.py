"""The observations dict of one agent: sensor uuid -> observation, as Habitat returns it.

Habitat-sim's ``sim.step`` and ``sim.get_sensor_observations`` return a plain ``dict`` keyed by
each sensor spec's ``uuid`` (plus ``"collided"`` after ``step``). :class:`Observations` is that
dict (a ``dict`` subclass: every dict operation, ``isinstance(obs, dict)``, pickling and
copying behave as Habitat's), with one difference a first script notices: reading a key that
is not there raises a ``KeyError`` that lists the keys that are, so ``obs["rgb"]`` on an agent
whose color camera is ``"color_sensor"`` says so.
"""

from __future__ import annotations

from typing import Any


class Observations(dict):
    """Sensor uuid -> observation; a missing key's ``KeyError`` names the uuids there are."""

    def __missing__(self, key: Any) -> Any:
        there = ", ".join(repr(k) for k in self) or "none (the agent has no sensors)"
        raise KeyError(
            f"no observation {key!r}: the keys are the uuids of the agent's sensor specs "
            f"(plus 'collided' after sim.step): {there}"
        )
