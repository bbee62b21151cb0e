"""Bad navmesh settings, queries and ``.navmesh`` files: refused, the old navmesh kept.

Navmesh settings and size budgets are refused before building; path-finder queries refuse
bad points, far points snap to nothing without overflow, oversized top-down views are
refused; a damaged ``.navmesh`` file (random bytes, truncated, inconsistent or huge arrays)
makes ``load_nav_mesh`` return False with a warning, as Habitat, and the navmesh loaded
before keeps working. Extreme but valid settings finish (work is bounded by the grid).
"""

from __future__ import annotations

import io
import math
import shutil
import tempfile
import warnings
import zipfile
from pathlib import Path

import numpy as np
import pytest
from bad_inputs import (
    BAD_INPUTS_CHECKED,
    EXAMPLES,
    assert_refused,
    bad_number,
    bad_vector,
    finite,
    junk,
    non_finite,
)
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from numpy.lib import format as npy_format
from world_hash import world_hash

import engine as habitat_sim
from navmesh import NavMeshSettings, PathFinder, ShortestPath

# -- navmesh settings, budgets, queries --------------------------------------------------------
NAV_FIELDS = {
    "cell_size": st.one_of(bad_number(0.0, low_open=True), st.floats(1e-6, 1e-3)),
    "cell_height": st.one_of(bad_number(0.0, low_open=True), st.floats(1e-7, 1e-5)),
    "agent_height": bad_number(0.0),  # 0 is accepted, as Habitat (test_agent_height_zero)
    "agent_radius": bad_number(0.0),
    "agent_max_climb": bad_number(0.0),
    "agent_max_slope": bad_number(0.0, 90.0),
    "region_min_size": bad_number(0.0),
    "filter_ledge_spans": st.one_of(junk, st.integers(), finite),
}


@EXAMPLES
@given(data=st.data())
def test_navmesh_settings_and_budgets_are_refused_before_building(sim, data):
    name = data.draw(st.sampled_from(sorted(NAV_FIELDS)), label="field")
    value = data.draw(NAV_FIELDS[name], label="value")
    nav_settings = NavMeshSettings()
    setattr(nav_settings, name, value)
    match = (
        "MAX_GRID_CELLS|MAX_RASTER_SAMPLES"
        if (name in ("cell_size", "cell_height") and isinstance(value, float) and 0 < value < 1e-2)
        else None
    )
    assert_refused(sim, lambda: sim.recompute_navmesh(sim.pathfinder, nav_settings), match=match)
    assert sim.pathfinder.is_loaded


QUERIES = {
    "snap_point": lambda pf, p: pf.snap_point(p),
    "is_navigable": lambda pf, p: pf.is_navigable(p),
    "get_island": lambda pf, p: pf.get_island(p),
    "try_step start": lambda pf, p: pf.try_step(p, [1.0, 0.0, 0.0]),
    "try_step end": lambda pf, p: pf.try_step([1.0, 0.0, 0.0], p),
    "try_step_no_sliding": lambda pf, p: pf.try_step_no_sliding(p, [1.0, 0.0, 0.0]),
    "find_path": lambda pf, p: pf.find_path(
        ShortestPath(requested_start=p, requested_end=[1, 0, 0])
    ),
    "distance_to_closest_obstacle": lambda pf, p: pf.distance_to_closest_obstacle(p),
    "random point near": lambda pf, p: pf.get_random_navigable_point_near(p, 1.0),
}


@EXAMPLES
@given(data=st.data())
def test_pathfinder_queries_refuse_bad_points(sim, data):
    name = data.draw(st.sampled_from(sorted(QUERIES)), label="query")
    value = data.draw(bad_vector(3), label="point")
    assert_refused(sim, lambda: QUERIES[name](sim.pathfinder, value))


@EXAMPLES
@given(
    point=st.lists(
        st.one_of(st.floats(-1.7e308, -1e12), st.floats(1e12, 1.7e308)), min_size=3, max_size=3
    )
)
def test_far_points_snap_to_nothing_without_overflow(sim, point):
    """Habitat's result for a point far from every polygon: NaN snap, the step stays put."""
    pf = sim.pathfinder
    before = world_hash(sim)
    assert np.all(np.isnan(pf.snap_point(point)))
    assert pf.get_island(point) == -1 and not pf.is_navigable(point)
    start = pf.get_random_navigable_point()
    np.testing.assert_array_equal(pf.try_step(point, start), np.asarray(point))
    assert np.all(np.isfinite(pf.try_step(start, point)))
    assert world_hash(sim) == before


@EXAMPLES
@given(
    mpp=st.one_of(bad_number(0.0, low_open=True), st.floats(1e-9, 1e-3)),
    height=st.one_of(finite, non_finite),
)
def test_topdown_views_over_the_budget_are_refused(sim, mpp, height):
    assert_refused(sim, lambda: sim.pathfinder.get_topdown_view(mpp, height))


# -- .navmesh files ---------------------------------------------------------------------------
@pytest.fixture(scope="module")
def navmesh_bytes(sim) -> bytes:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "good.navmesh"
        assert sim.pathfinder.save_nav_mesh(path)
        return path.read_bytes()


def _mutated_archive(good: bytes, key: str, how: str, rng: np.random.Generator) -> bytes:
    """The good archive with one array replaced by an inconsistent one."""
    arrays = dict(np.load(io.BytesIO(good)))
    array = arrays[key]
    if how == "shape":
        arrays[key] = np.zeros(
            (*array.shape[:-1], array.shape[-1] + 1) if array.ndim else (2,), dtype=array.dtype
        )
    elif how == "dtype":
        arrays[key] = np.full(array.shape, "x") if array.dtype.kind != "U" else np.array(7.0)
    elif how == "values":
        if array.dtype.kind in "iu":
            arrays[key] = rng.integers(-100, 100, array.shape).astype(array.dtype)
        elif array.dtype.kind == "f":
            arrays[key] = np.full(array.shape, rng.choice([math.nan, math.inf, -1.0, 0.0]))
        elif array.dtype.kind == "b":
            arrays[key] = ~array
        else:
            arrays[key] = np.array("{not json" if key == "settings_json" else "other")
    elif how == "missing":
        del arrays[key]
    stream = io.BytesIO()
    np.savez_compressed(stream, **arrays)
    if how == "huge":  # a header claiming 8 GB of floats in a few bytes: must not be read
        with zipfile.ZipFile(stream, "a") as archive:
            header = io.BytesIO()
            npy_format.write_array_header_1_0(
                header, {"descr": "<f8", "fortran_order": False, "shape": (1000, 1000, 1000)}
            )
            archive.writestr(f"{key}_huge.npy", header.getvalue() + bytes(64))
        stream = _renamed(stream.getvalue(), f"{key}_huge.npy", f"{key}.npy")
    return stream.getvalue()


def _renamed(content: bytes, old: str, new: str) -> io.BytesIO:
    """A copy of a zip archive where member ``old`` replaces member ``new``."""
    out = io.BytesIO()
    with zipfile.ZipFile(io.BytesIO(content)) as source, zipfile.ZipFile(out, "w") as target:
        for info in source.infolist():
            if info.filename == new:
                continue
            data = source.read(info.filename)
            target.writestr(new if info.filename == old else info.filename, data)
    return out


@settings(
    max_examples=40,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(data=st.data())
def test_bad_navmesh_files_are_refused_and_the_old_one_keeps_working(sim, navmesh_bytes, data):
    kind = data.draw(st.sampled_from(["bytes", "truncated", "array"]), label="kind")
    if kind == "bytes":
        content = data.draw(st.binary(max_size=64), label="bytes")
    elif kind == "truncated":
        content = navmesh_bytes[: data.draw(st.integers(0, len(navmesh_bytes) - 1), label="n")]
    else:
        key = data.draw(
            st.sampled_from(
                [
                    "floor",
                    "ceiling",
                    "navigable",
                    "links",
                    "island",
                    "bounds",
                    "origin_xz",
                    "cell_size",
                    "settings_json",
                    "format_version",
                ]
            ),
            label="key",
        )
        how = data.draw(
            st.sampled_from(["shape", "dtype", "values", "missing", "huge"]), label="how"
        )
        rng = np.random.default_rng(data.draw(st.integers(0, 1000), label="seed"))
        content = _mutated_archive(navmesh_bytes, key, how, rng)
        if content == navmesh_bytes:
            return
    pf = sim.pathfinder
    probe = pf.get_random_navigable_point()
    snapped = pf.snap_point(probe)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "bad.navmesh"
        path.write_bytes(content)
        before = world_hash(sim)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            loaded = pf.load_nav_mesh(path)
        if loaded:  # a mutation that kept the file consistent (floors all moved to -1 m)
            assert pf.load_nav_mesh(_write(folder, navmesh_bytes))
            return
        assert any("load_nav_mesh" in str(w.message) for w in caught)
        assert world_hash(sim) == before
        np.testing.assert_array_equal(pf.snap_point(probe), snapped)
        BAD_INPUTS_CHECKED["count"] += 1


def _write(folder: str, content: bytes) -> Path:
    path = Path(folder) / "restore.navmesh"
    path.write_bytes(content)
    return path


def test_a_bad_navmesh_beside_the_stage_leaves_the_simulator_without_one(demo_data, tmp_path):
    scene = demo_data / "scene_datasets/demo"
    for name in ("apartment.glb", "apartment.stage_config.json"):
        shutil.copy(scene / name, tmp_path / name)
    (tmp_path / "apartment.navmesh").write_bytes(b"")
    cfg = habitat_sim.SimulatorConfiguration()
    cfg.scene_id = str(tmp_path / "apartment.glb")
    with pytest.warns(UserWarning, match="not a valid navmesh"):
        simulator = habitat_sim.Simulator(habitat_sim.Configuration(cfg))
    assert not simulator.pathfinder.is_loaded
    simulator.close()


@pytest.mark.parametrize(
    "name, value",
    [
        ("agent_radius", 1e6),
        ("agent_radius", 1e300),
        ("region_min_size", 1e150),
        ("agent_max_climb", 1e6),
        ("cell_size", 1e3),
        ("agent_height", 1e300),
    ],
)
def test_extreme_but_valid_navmesh_settings_finish(name, value):
    """Work is bounded by the grid, not by the values: these used to hang or overflow."""
    floor = np.array([[0, 0, 0], [10, 0, 0], [10, 0, 10], [0, 0, 10]], np.float64)
    faces = np.array([[0, 2, 1], [0, 3, 2]], np.int64)
    nav_settings = NavMeshSettings()
    setattr(nav_settings, name, value)
    pathfinder = PathFinder()
    assert pathfinder.build(floor, faces, nav_settings)
    area = pathfinder.navigable_area
    if name in ("agent_radius", "region_min_size", "cell_size"):
        assert area == 0.0  # eroded away, or every island under region_min_size^2 cells
    else:
        assert 0.0 < area <= 100.0 + 1e-9
