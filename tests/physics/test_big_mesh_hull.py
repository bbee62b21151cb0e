"""A mesh object with many vertices on its hull (a finely tessellated smooth surface) is
added quickly: its collision hull is the hull of a capped vertex sample, computed once per
asset (``engine/physics/hull_sampling.py``).

Before: the hull of the full vertex set was computed five times per object (shape, face
planes, inertia, the speculative probe's two), and again for every object of the asset: an
82k-triangle ellipsoid took 18.8 s per object.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from engine.physics.core.settings import HULL_SAMPLE_POINTS, MAX_HULL_POINTS
from engine.physics.objects import hull_sampling
from engine.simulator import Configuration, Simulator, SimulatorConfiguration

HALF_AXES = np.array([0.3, 0.2, 0.25])  # m, the ellipsoid's semi-axes


@pytest.fixture
def ellipsoid_glb(tmp_path):
    """A smooth ellipsoid of 20480 triangles: all 10242 vertices lie on its hull."""
    sphere = trimesh.creation.icosphere(subdivisions=5)
    vertices = np.asarray(sphere.vertices) * HALF_AXES
    path = tmp_path / "ellipsoid.glb"
    trimesh.Trimesh(vertices, sphere.faces, process=False).export(path)
    return path, vertices


def test_a_mesh_with_thousands_of_hull_vertices_gets_one_capped_hull_per_asset(
    ellipsoid_glb, monkeypatch
):
    path, vertices = ellipsoid_glb
    assert len(vertices) > MAX_HULL_POINTS
    hulled = []  # point counts of every trimesh hull computed
    samples = []
    original_hull, original_sample = trimesh.convex.convex_hull, hull_sampling.hull_sample
    monkeypatch.setattr(
        trimesh.convex,
        "convex_hull",
        lambda p, *a, **k: hulled.append(len(p)) or original_hull(p, *a, **k),
    )
    monkeypatch.setattr(
        hull_sampling, "hull_sample", lambda p, *a: samples.append(len(p)) or original_sample(p, *a)
    )
    hull_sampling.clear_hull_cache()
    with Simulator(Configuration(SimulatorConfiguration(scene_id="NONE"))) as sim:
        templates = sim.get_object_template_manager()
        template_id = templates.register_template(templates.create_new_template(str(path)))
        handle = templates.get_template_by_id(template_id).handle
        manager = sim.get_rigid_object_manager()
        first = manager.add_object_by_template_handle(handle)
        second = manager.add_object_by_template_handle(handle)
        assert first.is_alive and second.is_alive
        assert samples == [len(vertices)]  # one sample for both objects of the asset
        assert max(hulled) <= HULL_SAMPLE_POINTS + 26  # never the full vertex set
        (shape,) = sim.get_physics_world().bodies.shapes[first.object_id]
        hull = shape.hull_vertices
        assert len(hull) <= HULL_SAMPLE_POINTS + 26
        # the bounding box is exact (the axis extremes are kept)
        np.testing.assert_allclose(hull.max(0) - hull.min(0), np.ptp(vertices, axis=0), atol=1e-9)
        # every mesh vertex is within 0.6 % of the size of the sampled hull (measured 0.46 %)
        center = 0.5 * (vertices.min(0) + vertices.max(0))
        outside = (vertices - center) @ shape.plane_normals.T - shape.plane_offsets
        assert outside.max() < 6e-3 * HALF_AXES.max()
        # and the body is what the full hull gives: mass properties within 1 %
        exact = trimesh.convex.convex_hull(vertices - center)
        per_kg = np.diag(exact.moment_inertia) / exact.volume
        np.testing.assert_allclose(
            np.asarray(first.intertia_diagonal), per_kg * first.mass, rtol=0.01
        )
