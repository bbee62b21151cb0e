"""Bad camera sensor specs and video arguments: a clear exception, nothing created.

A ``CameraSensorSpec`` with a bad field is refused when the sensor is created (no node is
left behind); ``make_video`` refuses empty frame lists and bad or oversized overlay dims
before writing anything.
"""

from __future__ import annotations

import math
import tempfile
from pathlib import Path

import numpy as np
import pytest
from bad_inputs import (
    EXAMPLES,
    assert_refused,
    bad_number,
    bad_vector,
    junk,
)
from hypothesis import given
from hypothesis import strategies as st

from engine.sensors import CameraSensor, CameraSensorSpec
from render import video as vut
from render.settings import MAX_PIXELS

# -- sensors -------------------------------------------------------------------------------------
SPEC_FIELDS = {
    "resolution": st.one_of(
        junk,
        st.lists(st.integers(-5, 0), min_size=2, max_size=2),
        st.tuples(st.sampled_from([math.nan, math.inf, 1.5, -3.0]), st.integers(1, 64)),
        st.tuples(st.integers(MAX_PIXELS // 64 + 1, 10**7), st.integers(65, 10**7)),
        st.lists(st.integers(1, 8), min_size=3, max_size=3),
    ),
    "hfov": st.one_of(bad_number(), st.floats(180, 1e9), st.floats(-1e9, 0)),
    "near": st.one_of(bad_number(), st.floats(-1e9, 0)),
    "far": st.one_of(bad_number(), st.floats(-1e9, 0.005)),
    "position": bad_vector(3),
    "orientation": bad_vector(3),
    "ortho_scale": st.one_of(bad_number(), st.floats(-1e9, 0)),
}


@EXAMPLES
@given(data=st.data())
def test_sensor_specs_are_refused_at_sensor_creation(sim, data):
    name = data.draw(st.sampled_from(sorted(SPEC_FIELDS)), label="field")
    value = data.draw(SPEC_FIELDS[name], label="value")
    spec = CameraSensorSpec()
    spec.uuid = "bad"
    setattr(spec, name, value)
    node = sim.agents[0].scene_node
    children = len(node.children)
    assert_refused(sim, lambda: CameraSensor(spec, node))
    assert len(node.children) == children


# -- videos --------------------------------------------------------------------------------------
@EXAMPLES
@given(
    dims=st.one_of(
        st.just("empty"),
        junk.filter(lambda v: v is not None),
        st.tuples(st.integers(-3, 0), st.integers(1, 8)),
        st.tuples(st.integers(MAX_PIXELS // 8 + 1, 10**9), st.integers(9, 10**9)),
    )
)
def test_make_video_refuses_empty_lists_and_bad_dims(sim, dims):
    frame = {"color": np.zeros((8, 8, 4), np.uint8)}
    with tempfile.TemporaryDirectory() as folder:
        target = str(Path(folder) / "clip")
        frames = [] if dims == "empty" else [frame]
        size = None if dims == "empty" else dims

        def call() -> None:
            vut.make_video(frames, "color", "color", target, open_vid=False, video_dims=size)

        assert_refused(sim, call, ValueError)
        assert not any(Path(folder).iterdir())  # nothing written


@pytest.mark.parametrize(
    ("fps", "shape"),
    [(-5, (8, 8, 4)), (0, (8, 8, 4)), (float("nan"), (8, 8, 4)), (True, (8, 8, 4)),
     (30, (0, 0, 4)), (30, (1, 1, 4)), (30, (8, 0, 4))],
)  # fmt: skip
def test_make_video_refuses_bad_fps_and_empty_frames_before_writing(fps, shape):
    # before the fix, both returned a file name and wrote nothing: a silent loss
    frames = [{"color": np.zeros(shape, np.uint8)}] * 3
    with tempfile.TemporaryDirectory() as folder:
        target = str(Path(folder) / "clip")
        with pytest.raises(ValueError, match="fps|height and width"):
            vut.make_video(frames, "color", "color", target, fps=fps, open_vid=False)
        assert not any(Path(folder).iterdir())  # nothing written
        with pytest.raises(ValueError, match="fps|height and width"):
            vut.save_video(target + ".mp4", [f["color"] for f in frames], fps=fps)
        assert not any(Path(folder).iterdir())
