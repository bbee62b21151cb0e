"""render.video: the behaviours of Habitat's tests/test_viz_utils.py, plus encoding."""

from __future__ import annotations

from functools import partial

import imageio
import numpy as np
import pytest
from PIL import Image

from render import video
from render.video import (
    D3_40_COLORS_RGB,
    border_frames_from_overlay,
    depth_to_rgb,
    display_video,
    is_notebook,
    make_video,
    make_video_frame,
    observation_to_image,
    semantic_to_rgb,
)

# -- depth_to_rgb ---------------------------------------------------------------------------


def test_depth_to_rgb_dtype_and_shape():
    result = depth_to_rgb(np.ones((10, 20), np.float32) * 5.0)
    assert result.dtype == np.uint8 and result.shape == (10, 20)


@pytest.mark.parametrize(
    "value, clip_max, expected",
    [(0.0, 10.0, 0), (10.0, 10.0, 255), (100.0, 10.0, 255), (-5.0, 10.0, 0), (2.0, 2.0, 255)],
)
def test_depth_to_rgb_clips_and_scales(value, clip_max, expected):
    depth = np.full((2, 2), value, np.float32)
    np.testing.assert_array_equal(depth_to_rgb(depth, clip_max=clip_max), expected)


def test_depth_to_rgb_half_depth_and_monotonic():
    assert depth_to_rgb(np.array([[5.0]], np.float32))[0, 0] in (127, 128)
    ramp = depth_to_rgb(np.array([[0.0, 2.5, 5.0, 7.5, 10.0]], np.float32))
    assert np.all(np.diff(ramp[0].astype(int)) >= 0)


def test_depth_to_rgb_leaves_its_input_unchanged():
    depth = np.full((3, 3), 4.0, np.float32)
    depth_to_rgb(depth, clip_max=2.0)
    assert np.all(depth == 4.0)


# -- semantic_to_rgb ------------------------------------------------------------------------


def test_semantic_to_rgb_is_rgba_image_of_input_size():
    result = semantic_to_rgb(np.zeros((10, 20), np.int32))
    assert isinstance(result, Image.Image)
    assert result.mode == "RGBA" and result.size == (20, 10)


def test_semantic_ids_map_to_palette_modulo_40():
    pixels = np.array(semantic_to_rgb(np.array([[0, 1, 40, 83]], np.uint32)))[0]
    assert not np.array_equal(pixels[0], pixels[1])
    np.testing.assert_array_equal(pixels[0], pixels[2])  # 40 % 40 == 0
    np.testing.assert_array_equal(pixels[3], [*D3_40_COLORS_RGB[83 % 40], 255])
    assert len({tuple(c) for c in D3_40_COLORS_RGB}) == 40


# -- observation_to_image -------------------------------------------------------------------


def test_observation_to_image_types():
    rng = np.random.default_rng(0)
    color = observation_to_image(rng.integers(0, 255, (48, 64, 4), dtype=np.uint8), "color")
    assert isinstance(color, Image.Image) and color.size == (64, 48)
    depth = observation_to_image(rng.random((48, 64), np.float32) * 10, "depth", depth_clip=10.0)
    assert isinstance(depth, Image.Image)
    semantic = observation_to_image(rng.integers(0, 20, (48, 64)), "semantic")
    assert isinstance(semantic, Image.Image)
    assert observation_to_image(np.zeros((4, 4), np.uint8), "unknown_type") is None


def test_observation_to_image_depth_clip_changes_brightness():
    obs = np.ones((4, 4), np.float32) * 5.0
    dim = np.array(observation_to_image(obs, "depth", depth_clip=10.0))
    bright = np.array(observation_to_image(obs, "depth", depth_clip=5.0))
    assert bright.mean() > dim.mean()
    assert np.all(bright == 255)


# -- border_frames_from_overlay -------------------------------------------------------------


def test_border_frames_none_or_empty_gives_empty_list():
    assert border_frames_from_overlay(None) == []
    assert border_frames_from_overlay([]) == []


def test_border_frames_size_count_and_color():
    frames = border_frames_from_overlay([{"dims": (100, 80), "border": 5}])
    assert len(frames) == 1 and isinstance(frames[0], Image.Image)
    assert frames[0].size == (110, 90)  # dims + 2 * border, PIL (width, height)
    assert np.all(np.array(frames[0]) == 150)
    two = border_frames_from_overlay(
        [{"dims": (50, 50), "border": 2}, {"dims": (30, 30), "border": 4}]
    )
    assert len(two) == 2
    red = border_frames_from_overlay([{"dims": (10, 10), "border": 1, "border_color": [255, 0, 0]}])
    assert np.all(np.array(red[0]) == [255, 0, 0])


# -- make_video_frame -----------------------------------------------------------------------


def test_make_video_frame_basic_and_resized():
    obs = {"color": np.random.default_rng(1).integers(0, 255, (48, 64, 4), dtype=np.uint8)}
    frame = make_video_frame(obs, "color", "color", video_dims=None)
    assert isinstance(frame, Image.Image) and frame.size == (64, 48)
    assert make_video_frame(obs, "color", "color", video_dims=(320, 240)).size == (320, 240)


def test_make_video_frame_failed_primary_raises():
    def bad_obs_to_image(img, obs_type, depth_clip=10.0):
        return None

    with pytest.raises(RuntimeError, match="primary image processing failed"):
        make_video_frame(
            {"color": np.zeros((4, 4, 4), np.uint8)}, "color", "color", None,
            observation_to_image=bad_obs_to_image,
        )  # fmt: skip


def test_make_video_frame_pastes_bordered_overlay():
    obs = {
        "color": np.zeros((100, 100, 4), np.uint8),
        "depth": np.full((100, 100), 10.0, np.float32),  # white after depth_to_rgb
    }
    overlay = [{"obs": "depth", "type": "depth", "dims": (40, 40), "pos": (5, 5), "border": 2}]
    frame = np.array(make_video_frame(obs, "color", "color", None, overlay_settings=overlay))
    assert np.all(frame[5:45, 5:45, :3] == 255)  # the overlay
    assert np.all(frame[3, 3:47, :3] == 150)  # its gray border
    assert np.all(frame[60:, 60:, :3] == 0)  # the primary image elsewhere


# -- is_notebook, display_video -------------------------------------------------------------


def test_is_notebook_false_in_a_script():
    assert is_notebook() is False


def test_display_video_headless_prints_the_path(capsys, tmp_path):
    display_video(str(tmp_path / "missing.mp4"))
    assert "missing.mp4" in capsys.readouterr().out


def test_display_video_in_a_notebook_emits_inline_html(monkeypatch, tmp_path):
    pytest.importorskip("IPython")
    import IPython.display

    path = tmp_path / "clip.mp4"
    path.write_bytes(b"not really a video")
    shown = []
    monkeypatch.setattr(video, "is_notebook", lambda: True)
    monkeypatch.setattr(IPython.display, "display", lambda obj: shown.append(obj))
    display_video(str(path), height=123)
    assert len(shown) == 1
    html = shown[0].data
    assert "<video" in html and "height: 123px" in html and "base64," in html


# -- make_video -----------------------------------------------------------------------------


def observations(n: int, h: int = 32, w: int = 48) -> list[dict]:
    """n observation dicts with color, depth and semantic images."""
    out = []
    for i in range(n):
        color = np.zeros((h, w, 4), np.uint8)
        color[..., 0] = (i * 40) % 256
        color[..., 3] = 255
        depth = np.full((h, w), i * 0.5, np.float32)
        semantic = np.full((h, w), i, np.uint32)
        out.append({"rgba": color, "depth": depth, "semantic": semantic})
    return out


def test_make_video_appends_mp4_and_writes_every_frame(tmp_path, capsys):
    written = make_video(
        observations(5), "rgba", "color", str(tmp_path / "clip"), fps=10, open_vid=True
    )
    assert written == str(tmp_path / "clip.mp4")
    with imageio.get_reader(written) as reader:
        assert reader.count_frames() == 5
        first = reader.get_data(0)
    assert first.shape[:2] == (32, 48)
    assert "clip.mp4" in capsys.readouterr().out  # open_vid on a headless run: path printed


@pytest.mark.parametrize("kind", ["depth", "semantic"])
def test_make_video_with_depth_or_semantic_primary_and_overlay(tmp_path, kind):
    overlay = [{"obs": "rgba", "type": "color", "dims": (12, 8), "pos": (2, 2), "border": 1}]
    written = make_video(
        observations(3), kind, kind, str(tmp_path / f"{kind}.mp4"), fps=5, open_vid=False,
        video_dims=(64, 40), overlay_settings=overlay,
    )  # fmt: skip
    with imageio.get_reader(written) as reader:
        assert reader.count_frames() == 3
        assert reader.get_data(0).shape[:2] == (40, 64)


def test_make_video_falls_back_to_gif_when_mp4_encoding_fails(tmp_path, monkeypatch):
    real_get_writer = imageio.get_writer

    def no_ffmpeg(path, *args, **kwargs):
        if kwargs.get("format") == "FFMPEG":
            raise RuntimeError("no ffmpeg here")
        return real_get_writer(path, *args, **kwargs)

    monkeypatch.setattr(imageio, "get_writer", no_ffmpeg)
    written = make_video(
        observations(4), "rgba", "color", str(tmp_path / "clip"), fps=10, open_vid=False
    )
    assert written == str(tmp_path / "clip.gif")
    frames = imageio.mimread(written)
    assert len(frames) == 4


def test_long_videos_show_a_progress_bar(tmp_path, capsys):
    make_video(
        observations(101, 8, 8), "rgba", "color", str(tmp_path / "long"), fps=60, open_vid=False
    )
    assert "Encoding video" in capsys.readouterr().err
    make_video(
        observations(10, 8, 8), "rgba", "color", str(tmp_path / "short"), fps=60, open_vid=False
    )
    assert "Encoding video" not in capsys.readouterr().err


# -- compose_video_frame (NumPy) against make_video_frame (PIL) -----------------------------


def random_observation(h: int = 54, w: int = 72, seed: int = 3) -> dict:
    rng = np.random.default_rng(seed)
    return {
        "rgba": rng.integers(0, 256, (h, w, 4), dtype=np.uint8),
        "opaque": np.dstack(  # a rendered frame: alpha 255 everywhere
            [rng.integers(0, 256, (h, w, 3), dtype=np.uint8), np.full((h, w), 255, np.uint8)]
        ),
        "rgb": rng.integers(0, 256, (h, w, 3), dtype=np.uint8),
        "depth": rng.uniform(0.0, 14.0, (h, w)).astype(np.float32),
        "semantic": rng.integers(0, 2**32, (h, w), dtype=np.uint32),
    }


OVERLAY_CASES = {
    "none": None,
    "tutorial": [
        {"obs": "rgba", "type": "color", "dims": (18, 13), "pos": (10, 10), "border": 2},
        {"obs": "depth", "type": "depth", "dims": (18, 13), "pos": (10, 33), "border": 2},
    ],
    "tutorial, opaque color": [  # read as RGB, alpha dropped (video._resized_overlay)
        {"obs": "opaque", "type": "color", "dims": (18, 13), "pos": (10, 10), "border": 2},
        {"obs": "depth", "type": "depth", "dims": (18, 13), "pos": (10, 33), "border": 2},
        {"obs": "opaque", "type": "color", "dims": (100, 70), "pos": (1, 2), "border": 0},
    ],
    "semantic, upscaled, clipped, colored": [
        {
            "obs": "semantic",
            "type": "semantic",
            "dims": (90, 20),
            "pos": (-5, 40),
            "border": 3,
            "border_color": (255, 10, 0),
        },
        {"obs": "rgb", "type": "color", "dims": (7, 9), "pos": (70, -1), "border": 1},
        {"obs": "rgba", "type": "color", "dims": (5, 5), "pos": (200, 200), "border": 1},
    ],
}


@pytest.mark.parametrize("case", list(OVERLAY_CASES))
@pytest.mark.parametrize("primary", ["rgba", "rgb", "depth", "semantic"])
def test_numpy_composition_equals_the_pil_frame_bit_for_bit(primary, case):
    obs = random_observation()
    kind = {"rgba": "color", "rgb": "color"}.get(primary, primary)
    overlays = OVERLAY_CASES[case]
    for clip in (10.0, 4.0):
        to_image = partial(observation_to_image, depth_clip=clip)
        reference = np.asarray(make_video_frame(obs, primary, kind, None, overlays, to_image))
        composed = video.compose_video_frame(obs, primary, kind, overlays, depth_clip=clip)
        assert composed.dtype == np.uint8 and composed.shape == reference.shape
        assert composed.tobytes() == reference.tobytes()


def test_numpy_composition_leaves_the_observation_unchanged_and_rejects_bad_types():
    obs = random_observation()
    before = {k: v.copy() for k, v in obs.items()}
    video.compose_video_frame(obs, "rgba", "color", OVERLAY_CASES["tutorial"])
    assert all(np.array_equal(obs[k], before[k]) for k in obs)
    with pytest.raises(RuntimeError, match="primary image processing failed"):
        video.compose_video_frame(obs, "rgba", "normals")
    bad = [{"obs": "rgba", "type": "normals", "dims": (4, 4), "pos": (0, 0), "border": 1}]
    with pytest.raises(RuntimeError, match="overlay image processing failed"):
        video.compose_video_frame(obs, "rgba", "color", bad)


def test_background_writer_writes_every_frame_and_raises_thread_errors(tmp_path):
    frames = [np.full((16, 24, 3), 20 * i, np.uint8) for i in range(6)]
    path = str(tmp_path / "bg.mp4")
    options = {"fps": 10, "format": "FFMPEG", "macro_block_size": 1}
    with video.BackgroundVideoWriter(path, options, prepare=lambda i: frames[i]) as writer:
        for i in range(len(frames)):
            writer.append(i)
    assert writer.frames == 6 and writer.busy_seconds > 0.0
    with imageio.get_reader(path) as reader:
        assert reader.count_frames() == 6
        assert abs(int(reader.get_data(5)[8, 12, 0]) - 100) <= 3

    def explode(item):
        raise ValueError(f"cannot prepare {item}")

    writer = video.BackgroundVideoWriter(str(tmp_path / "bad.mp4"), options, prepare=explode)
    writer.append(1)
    with pytest.raises(ValueError, match="cannot prepare 1"):
        for i in range(100):  # the thread's error surfaces on a later append or on close
            writer.append(i)
        writer.close()
    writer.close()  # the error was reported once; closing again is quiet


def test_make_video_hands_the_encoder_the_pil_frames_in_order(monkeypatch, tmp_path):
    captured = []

    def capture(video_file, frames, fps=60, n_frames=None):
        captured.extend(frames())
        return video_file

    monkeypatch.setattr(video, "save_video", capture)
    obs = [random_observation(seed=s) for s in range(9)]
    overlays = OVERLAY_CASES["tutorial"]
    make_video(obs, "rgba", "color", str(tmp_path / "v"), open_vid=False,
               overlay_settings=overlays, depth_clip=6.0)  # fmt: skip
    to_image = partial(observation_to_image, depth_clip=6.0)
    expected = [make_video_frame(o, "rgba", "color", None, overlays, to_image) for o in obs]
    assert len(captured) == len(expected)
    for got, want in zip(captured, expected, strict=True):
        assert got.tobytes() == np.asarray(want).tobytes()


def test_opaque_rgba_overlays_take_the_rgbx_path_and_others_do_not(monkeypatch):
    obs = random_observation()
    calls = []
    original = video.observation_to_image
    monkeypatch.setattr(
        video, "observation_to_image", lambda *a, **k: calls.append(a[1]) or original(*a, **k)
    )
    video.compose_video_frame(obs, "rgb", "color", OVERLAY_CASES["tutorial, opaque color"])
    assert calls == ["depth"]  # both opaque color overlays were resized from their buffer
    calls.clear()
    video.compose_video_frame(obs, "rgb", "color", OVERLAY_CASES["tutorial"])
    assert calls == ["color", "depth"]  # random alpha: PIL's premultiplied RGBA resize


def test_to_even_frame_layouts():
    rgb = np.arange(5 * 7 * 3, dtype=np.uint8).reshape(5, 7, 3)
    rgba = np.dstack([rgb, np.full((5, 7), 9, np.uint8)])
    assert video._to_even_frame(rgba, 3).tobytes() == rgb[:4, :6].copy().tobytes()
    as_rgba = video._to_even_frame(rgb, 4)
    assert as_rgba.shape == (4, 6, 4) and np.all(as_rgba[..., 3] == 255)
    assert np.array_equal(as_rgba[..., :3], rgb[:4, :6])
    gray = video._to_even_frame(rgb[..., 0], 4)
    assert np.array_equal(gray[..., 1], rgb[:4, :6, 0]) and np.all(gray[..., 3] == 255)


def test_rgba_frames_encode_like_rgb_frames(tmp_path):
    """RGBA frames go to ffmpeg as they are (alpha ignored): the decoded video is the one
    the same frames give as RGB, also when RGB frames follow an RGBA first frame."""
    rng = np.random.default_rng(5)
    rgb = [rng.integers(0, 256, (32, 48, 3), dtype=np.uint8) for _ in range(4)]
    rgba = [np.dstack([f, np.full((32, 48), 255, np.uint8)]) for f in rgb]
    options = {"fps": 10, "format": "FFMPEG", "macro_block_size": 1}
    decoded = {}
    for name, frames in (("rgb", rgb), ("rgba", rgba), ("mixed", rgba[:2] + rgb[2:])):
        path = str(tmp_path / f"{name}.mp4")
        with video.BackgroundVideoWriter(path, options) as writer:
            for frame in frames:
                writer.append(frame)
        decoded[name] = np.stack(imageio.mimread(path))
    assert decoded["rgb"].shape[0] == 4
    assert np.array_equal(decoded["rgba"], decoded["rgb"])
    assert np.array_equal(decoded["mixed"], decoded["rgb"])
