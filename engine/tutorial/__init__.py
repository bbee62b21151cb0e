"""Habitat's "Interactive Rigid Objects via PhysicsObjectManager" tutorial as a program.

``python -m engine.tutorial [--output-dir DIR] [--no-make-video] [--fast] [--seed N]`` runs
every section of Habitat-sim's managed rigid object tutorial (basics, user attributes,
dynamic control, kinematic interactions, kinematic update, velocity control, local velocity
control, embodied agent, embodied agent on the navmesh with and without sliding) on the demo
apartment and writes the nine videos, ``summary.json`` and a timing table.

The tutorial is Habitat-sim's ``examples/tutorials/nb_python/managed_rigid_object_tutorial.py``
(MIT License, Copyright (c) Meta Platforms, Inc. and its affiliates); this package keeps its
code structure and names. Modules:

- :mod:`~engine.tutorial.scene_setup`: configuration, sensors, agent placement;
- :mod:`~engine.tutorial.recording`: stepping, rendering and streaming video, timed;
- :mod:`~engine.tutorial.context`: the context sections share and the result they return;
- :mod:`~engine.tutorial.sections_objects`, :mod:`~engine.tutorial.sections_control`,
  :mod:`~engine.tutorial.sections_agent`: the sections, one function each;
- :mod:`~engine.tutorial.report`: summary table and ``summary.json``;
- :mod:`~engine.tutorial.cli`: :func:`run_tutorial` and the command line.

May import: the whole ``engine`` through ``import engine as habitat_sim`` (as Habitat's
tutorial does), ``engine.batch``, ``engine.demo`` and ``render.video``; only the viewer's
demo replay imports it.
"""

from engine.tutorial.cli import SECTIONS, main, run_tutorial
from engine.tutorial.context import SectionResult, TutorialContext

__all__ = ["SECTIONS", "SectionResult", "TutorialContext", "main", "run_tutorial"]
