"""NavMeshSettings: Habitat defaults, camelCase JSON, equality with 1e-5 tolerance, validation."""

from __future__ import annotations

import json

import pytest

from navmesh import NavMeshSettings


def test_defaults_match_habitat_set_defaults():
    s = NavMeshSettings()
    assert (s.cell_size, s.cell_height, s.agent_height) == (0.05, 0.2, 1.5)
    assert (s.agent_radius, s.agent_max_climb, s.agent_max_slope) == (0.1, 0.2, 45.0)
    assert (s.region_min_size, s.region_merge_size, s.edge_max_len) == (20.0, 20.0, 12.0)
    assert (s.edge_max_error, s.verts_per_poly) == (1.3, 6.0)
    assert (s.detail_sample_dist, s.detail_sample_max_error) == (6.0, 1.0)
    assert s.filter_low_hanging_obstacles and s.filter_ledge_spans
    assert s.filter_walkable_low_height_spans and not s.include_static_objects


def test_set_defaults_restores_every_field():
    s = NavMeshSettings()
    s.agent_radius, s.filter_ledge_spans, s.include_static_objects = 0.5, False, True
    assert s != NavMeshSettings()
    s.set_defaults()
    assert s == NavMeshSettings()


def test_read_habitat_test_json(test_assets):
    s = NavMeshSettings()
    s.read_from_json(test_assets / "test_navmeshsettings.json")
    assert s.cell_size == pytest.approx(0.0123)
    assert s.agent_height == pytest.approx(1.2345)
    assert s.agent_max_slope == pytest.approx(34.0)
    assert s.verts_per_poly == pytest.approx(9.0)
    assert not s.filter_low_hanging_obstacles and not s.filter_walkable_low_height_spans


def test_json_round_trip_uses_camel_case_keys(tmp_path, test_assets):
    s = NavMeshSettings()
    s.read_from_json(test_assets / "test_navmeshsettings.json")
    out = tmp_path / "settings.json"
    s.write_to_json(out)
    keys = json.loads(out.read_text())
    assert {"cellSize", "agentRadius", "agentMaxClimb", "filterLedgeSpans"} <= set(keys)
    again = NavMeshSettings()
    again.read_from_json(out)
    assert again == s


def test_equality_tolerance_is_1e_5():
    a, b = NavMeshSettings(), NavMeshSettings()
    b.agent_radius += 5e-6
    assert a == b
    b.agent_radius += 5e-5
    assert a != b


@pytest.mark.parametrize(
    ("field", "value", "error"),
    [
        ("cell_size", 0.0, ValueError),
        ("cell_size", float("nan"), ValueError),
        ("agent_radius", -0.1, ValueError),
        ("agent_max_slope", 95.0, ValueError),
        ("agent_height", float("inf"), ValueError),
        ("agent_height", "tall", TypeError),
        ("filter_ledge_spans", 1, TypeError),
    ],
)
def test_validate_names_the_bad_field(field, value, error):
    s = NavMeshSettings()
    setattr(s, field, value)
    with pytest.raises(error, match=field):
        s.validate()


def test_bad_json_leaves_settings_unchanged(tmp_path):
    s = NavMeshSettings()
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"cellSize": 0.1, "agentRadius": -1.0}))
    with pytest.raises(ValueError, match="agent_radius"):
        s.read_from_json(bad)
    assert s == NavMeshSettings()
    bad.write_text(json.dumps({"cellSiz": 0.1}))
    with pytest.raises(KeyError, match="cellSiz"):
        s.read_from_json(bad)
    bad.write_text("{not json")
    with pytest.raises(ValueError, match="malformed"):
        s.read_from_json(bad)
    with pytest.raises(FileNotFoundError):
        s.read_from_json(tmp_path / "missing.json")
