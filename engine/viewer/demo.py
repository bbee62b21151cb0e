"""The tutorial's scene as a replay: cans landing on a kinematic can, contact normals drawn.

The scene is the ``[kinematic_interactions]`` block of Habitat-sim's managed rigid object
tutorial (MIT License, Copyright (c) Meta Platforms, Inc. and its affiliates), as rigidsim's
tutorial runs it (:mod:`engine.tutorial.sections_objects`): the demo apartment, a KINEMATIC
chef can on the table and three DYNAMIC chef cans dropped on and around it. The replay shows
them land, the contact normals grow with the impulses and the cans fall asleep (tinted by
island).

``python -m engine.viewer --demo-replay OUT.html`` writes it; the documentation build embeds
it as ``replays/tutorial_replay.html``.
"""

from __future__ import annotations

import os
from pathlib import Path

import engine as habitat_sim
from engine.tutorial.scene_setup import (
    FAST_RESOLUTION,
    FRAME_DT,
    make_configuration,
    place_agent,
)
from engine.viewer.replay import Replay
from engine.viewer.viewer import Viewer

__all__ = ["DEMO_SECONDS", "make_tutorial_scene", "record_tutorial_replay"]

#: s of world time recorded: the cans land within 1 s and sleep by about 2.5 s
DEMO_SECONDS = 3.0
#: camera [eye, target, up] looking at the table from the room (world frame, meters)
DEMO_CAMERA = [3.6, 0.1, 1.1, 2.4, -0.6, 0.0, 0.0, 1.0, 0.0]


def make_tutorial_scene(data_path: str | None = None) -> habitat_sim.Simulator:
    """The tutorial's simulator with the ``[kinematic_interactions]`` cans placed.

    ``data_path`` is the demo dataset folder (:func:`engine.demo.demo_data_path` when None).
    Sensors render small frames: the replay does not render them.
    """
    if data_path is None:
        from engine.demo import demo_data_path

        data_path = str(demo_data_path())
    sim = habitat_sim.Simulator(make_configuration(data_path, FAST_RESOLUTION))
    place_agent(sim)
    obj_templates_mgr = sim.get_object_template_manager()
    rigid_obj_mgr = sim.get_rigid_object_manager()
    obj_templates_mgr.load_configs(str(os.path.join(data_path, "objects/example_objects/")))
    chefcan_template_handle = obj_templates_mgr.get_template_handles(
        "data/objects/example_objects/chefcan"
    )[0]
    chefcan_obj = rigid_obj_mgr.add_object_by_template_handle(chefcan_template_handle)
    chefcan_obj.translation = [2.4, -0.64, 0.0]
    chefcan_obj.motion_type = habitat_sim.physics.MotionType.KINEMATIC
    for position in ([2.4, -0.64, 0.28], [2.4, -0.64, -0.28], [2.4, -0.3, 0.0]):
        can = rigid_obj_mgr.add_object_by_template_handle(chefcan_template_handle)
        can.translation = position
    return sim


def record_tutorial_replay(
    seconds: float = DEMO_SECONDS, data_path: str | None = None, every: int = 2
) -> Replay:
    """Step the tutorial scene for ``seconds`` at 60 Hz and record every ``every``-th frame."""
    if not seconds > 0:
        raise ValueError(f"seconds must be positive, got {seconds!r}")
    if isinstance(every, bool) or not isinstance(every, int) or every < 1:
        raise ValueError(f"every must be a positive int, got {every!r}")
    sim = make_tutorial_scene(data_path)
    try:
        viewer = Viewer(sim, camera=DEMO_CAMERA)
        viewer.start_recording()
        n_frames = round(seconds / FRAME_DT)
        for frame in range(1, n_frames + 1):
            sim.step_physics(FRAME_DT)
            if frame % every == 0:
                viewer.update()
        return viewer.replay()
    finally:
        sim.close()


def write_tutorial_replay(path: str | Path, seconds: float = DEMO_SECONDS) -> Path:
    """Record :func:`record_tutorial_replay` and write it as self-contained HTML."""
    return record_tutorial_replay(seconds).save(path)
