"""Unit tests of the collision and solver building blocks against the reference path.

* the batched narrow phase against :func:`reference_contacts.pair_contacts`, pair by pair;
* :class:`ManifoldStore` (rows, mapping protocol, refresh, matching, reduction) against
  :func:`reference_contacts.update_manifold` and hand-made cases;
* the batched Jacobians / effective masses against the reference's own build and a hand
  value; the quaternion coefficient tables against :mod:`engine.mn`'s formulas.
"""

from __future__ import annotations

import copy
from collections.abc import MutableMapping

import numpy as np
import pytest
from helpers import add, make_world, register_primitive, run
from test_reference_path import CONE, CYLINDER

from engine import mn
from engine.physics.collision import batched_stage
from engine.physics.collision.contacts import FreshPoints, ManifoldStore
from engine.physics.core import settings
from engine.physics.core.quaternions import cross, quat_multiply, quat_to_matrix
from engine.physics.pipeline.collision_stage import (
    broad_phase,
    touching_candidates,
    update_manifolds,
)
from engine.physics.pipeline.narrow_phase import narrow_phase
from engine.physics.pipeline.reference_contacts import (
    Contact,
    ManifoldPoint,
    pair_contacts,
    update_manifold,
    update_manifolds_reference,
)

IDENTITY = (np.eye(3), np.zeros(3))
FIELDS = ("local_a", "local_b", "normal_local", "impulse")


def tumbling_world(seconds: float):
    """Boxes, cylinders and cones tumbling on the floor after ``seconds``."""
    world, templates = make_world()
    handles = [
        register_primitive(templates, name, (0.1, 0.1, 0.1))
        for name in ("cubeSolid", CYLINDER, CONE)
    ]
    rng = np.random.default_rng(11)
    for k in range(9):
        body = add(
            world,
            templates,
            handles[k % 3],
            [0.21 * (k % 3) - 0.21, 0.15 + 0.22 * (k // 3), rng.uniform(-0.05, 0.05)],
        )
        q = rng.normal(size=4)
        body.rotation = mn.Quaternion.from_xyzw(q / np.linalg.norm(q))
    run(world, seconds)
    return world


def candidate_pairs(world):
    b, n = world.bodies, world.bodies.count
    rotation = quat_to_matrix(b.body_rotation[:n])
    pairs, _ = broad_phase(b)
    pairs = touching_candidates(b, world.manifolds, pairs, rotation)
    for a, c in pairs:  # the collision stage moves the fcl objects of the pairs it tests
        for index in (a, c):
            if index:
                world._update_fcl(index)
    return pairs, rotation


@pytest.mark.parametrize("seconds", [0.1, 0.4, 0.8])
def test_batched_narrow_phase_matches_the_per_pair_reference(seconds):
    world = tumbling_world(seconds)
    pairs, rotation = candidate_pairs(world)
    position, point_a, point_b, normal, _ = narrow_phase(
        world.bodies, world.collision_objects, world.manifolds, pairs, rotation
    )
    n_points = 0
    for k, (a, c) in enumerate(pairs):
        reference = pair_contacts(
            world.bodies, world.collision_objects, world.manifolds, a, c, rotation
        )
        mine = position == k
        assert len(reference) == mine.sum(), (a, c)
        for contact, pa, pb, n in zip(
            reference, point_a[mine], point_b[mine], normal[mine], strict=True
        ):
            # same formulas, sums rounded in another order: agreement to 1e-12 m
            np.testing.assert_allclose(contact.point_a, pa, atol=1e-12)
            np.testing.assert_allclose(contact.point_b, pb, atol=1e-12)
            np.testing.assert_allclose(contact.normal, n, atol=1e-12)
        n_points += len(reference)
    assert n_points > 10  # the scene really has contacts


@pytest.mark.parametrize("seconds", [0.2, 0.6])
def test_batched_manifold_update_matches_the_per_pair_reference(seconds):
    world = tumbling_world(seconds)
    pairs, rotation = candidate_pairs(world)
    batched, reference = copy.deepcopy(world.manifolds), copy.deepcopy(world.manifolds)
    update_manifolds(world.bodies, world.collision_objects, batched, pairs, rotation)
    update_manifolds_reference(world.bodies, world.collision_objects, reference, pairs, rotation)
    assert sorted(batched) == sorted(reference)
    for key in batched:
        row_b, row_r = batched.row(key), reference.row(key)
        assert batched.count[row_b] == reference.count[row_r], key
        for name in ("local_a", "local_b", "normal_local", "impulse"):
            np.testing.assert_allclose(
                getattr(batched, name)[row_b], getattr(reference, name)[row_r], atol=1e-12
            )


# -- ManifoldStore: rows and the mapping protocol --------------------------------------------
def test_store_rows_are_reused_lowest_first_and_iterate_in_insertion_order():
    store = ManifoldStore(capacity=2)
    rows = [store.add((0, k), 4) for k in (3, 1, 2)]  # the third add grows the arrays
    assert rows == [0, 1, 2] and len(store.count) >= 3
    assert list(store) == [(0, 3), (0, 1), (0, 2)]
    store.count[1], store.impulse[1, 0] = 1, [5.0, 0.0, 0.0]
    del store[(0, 1)]
    assert (0, 1) not in store and store.count[1] == 0 and not store.impulse[1].any()
    assert store.add((4, 5), 1) == 1  # the freed row comes back first
    with pytest.raises(TypeError, match="ManifoldStore.add"):
        store[(6, 7)] = None
    store.clear()
    assert len(store) == 0 and not store.count.any()


def fresh_points(points_b, normal=(0.0, 1.0, 0.0), depth=0.001) -> FreshPoints:
    """One row of fresh points with B's anchors ``points_b`` and A's ``depth`` along n."""
    points_b = np.asarray(points_b, dtype=np.float64)
    normal = np.tile(normal, (len(points_b), 1))
    return FreshPoints(
        1, np.zeros(len(points_b), dtype=np.int64), points_b + depth * normal, points_b, normal
    )


def store_with_row(max_points: int = 4):
    store = ManifoldStore()
    store.add((0, 1), max_points)
    rotation, position = np.tile(np.eye(3), (2, 1, 1)), np.zeros((2, 3))
    return store, rotation, position


def test_the_store_is_a_mapping_whose_update_keeps_its_mapping_meaning():
    # the step's merge is merge_fresh; update is MutableMapping's (key -> manifold)
    assert ManifoldStore.update is MutableMapping.update
    store, _, _ = store_with_row()
    store.update({})  # nothing to set: no error, no change
    assert len(store) == 1


def test_nine_coplanar_points_reduce_to_the_four_corners():
    # a 20 cm square face on the floor: corners, edge midpoints and center, all equally deep
    grid = [[x, 0.0, z] for x in (-0.1, 0.0, 0.1) for z in (-0.1, 0.0, 0.1)]
    store, rotation, position = store_with_row()
    store.merge_fresh(np.array([0]), rotation, position, fresh_points(grid))
    corners = {(x, z) for x in (-0.1, 0.1) for z in (-0.1, 0.1)}
    kept = {(round(p[0], 9), round(p[2], 9)) for p in store.local_b[0, : store.count[0]]}
    assert store.count[0] == 4 and kept == corners  # the largest supporting area
    reference = update_manifold(
        [],
        [
            Contact(p + [0, 0.001, 0], np.array(p), np.array([0.0, 1.0, 0.0]))
            for p in np.array(grid)
        ],
        IDENTITY,
        IDENTITY,
        4,
    )
    assert {(round(p.local_b[0], 9), round(p.local_b[2], 9)) for p in reference} == corners


def test_matched_points_inherit_impulses_and_separated_points_are_dropped():
    store, rotation, position = store_with_row()
    store.merge_fresh(np.array([0]), rotation, position, fresh_points([[0.0, 0, 0], [0.1, 0, 0]]))
    store.impulse[0, :2] = [[1.0, 0.1, 0.2], [2.0, 0.3, 0.4]]
    # a fresh point 5 mm from the first cached one inherits its impulse (warm start); the
    # second cached point is still touching and kept with its own impulse
    store.merge_fresh(np.array([0]), rotation, position, fresh_points([[0.005, 0, 0]]))
    impulses = {
        round(p[0], 3): i.tolist()
        for p, i in zip(store.local_b[0], store.impulse[0], strict=True)
        if i.any()
    }
    assert impulses == {0.005: [1.0, 0.1, 0.2], 0.1: [2.0, 0.3, 0.4]}
    # B moves 3 cm away along the normal (+Y), beyond CONTACT_BREAKING_DISTANCE: all dropped
    position[1] = [0.0, 1.5 * settings.CONTACT_BREAKING_DISTANCE, 0.0]
    store.merge_fresh(np.array([0]), rotation, position, fresh_points(np.zeros((0, 3))))
    assert store.count[0] == 0


def test_two_fresh_points_near_one_cached_point_match_it_greedily_like_the_reference():
    # cached points at x = 0 and x = 0.1; fresh points 1.2 cm either side of x = 0 (2.4 cm
    # apart, both within the 2 cm match distance of it) and one 4 mm from the deepest (dropped
    # as not distinct). The deepest fresh point takes the cached impulse; the other one,
    # whose only candidate is taken, starts from zero. Batched and reference agree.
    store, rotation, position = store_with_row()
    store.merge_fresh(np.array([0]), rotation, position, fresh_points([[0.0, 0, 0], [0.1, 0, 0]]))
    store.impulse[0, :2] = [[1.0, 0.1, 0.2], [2.0, 0.3, 0.4]]
    cached = [
        ManifoldPoint(*(getattr(store, name)[0, k].copy() for name in FIELDS)) for k in range(2)
    ]
    points_b = np.array([[-0.012, 0.0, 0.0], [0.012, 0.0, 0.0], [0.016, 0.0, 0.0]])
    depth = np.array([0.001, 0.002, 0.0015])  # the point at +1.2 cm is the deepest
    normal = np.tile([0.0, 1.0, 0.0], (3, 1))
    point_a = points_b + depth[:, None] * normal
    fresh = FreshPoints(1, np.zeros(3, dtype=np.int64), point_a, points_b, normal)
    store.merge_fresh(np.array([0]), rotation, position, fresh)
    contacts = [Contact(a, b, n) for a, b, n in zip(point_a, points_b, normal, strict=True)]
    reference = update_manifold(cached, contacts, IDENTITY, IDENTITY, 4)
    assert store.count[0] == len(reference) == 3
    kept = zip(store.local_b[0, :3], store.impulse[0, :3], strict=True)
    impulses = {round(p[0], 4): i.tolist() for p, i in kept}
    assert impulses == {0.1: [2.0, 0.3, 0.4], 0.012: [1.0, 0.1, 0.2], -0.012: [0.0, 0.0, 0.0]}
    for name in FIELDS:
        np.testing.assert_array_equal(
            getattr(store, name)[0, :3], [getattr(p, name) for p in reference]
        )


def test_reference_manifold_update_matches_store_on_the_same_history():
    store, rotation, position = store_with_row()
    cached: list[ManifoldPoint] = []
    rng = np.random.default_rng(5)
    for _ in range(20):  # random fresh points on a 20 cm patch, some of them matching
        points = rng.uniform(-0.1, 0.1, size=(rng.integers(1, 7), 3)) * [1, 0, 1]
        depth = rng.uniform(-0.002, 0.004, size=len(points))
        fresh = FreshPoints(
            1,
            np.zeros(len(points), dtype=np.int64),
            points + depth[:, None] * [0, 1, 0],
            points,
            np.tile([0.0, 1.0, 0.0], (len(points), 1)),
        )
        store.merge_fresh(np.array([0]), rotation, position, fresh)
        contacts = [
            Contact(a, b, n)
            for a, b, n in zip(fresh.point_a[0], fresh.point_b[0], fresh.normal[0], strict=True)
        ]
        cached = update_manifold(cached, contacts[: len(points)], IDENTITY, IDENTITY, 4)
        store.impulse[0, : store.count[0], 0] = np.arange(1, store.count[0] + 1)  # tag slots
        for k, point in enumerate(cached):
            point.impulse = np.array([k + 1.0, 0.0, 0.0])
        assert store.count[0] == len(cached)
        np.testing.assert_allclose(
            store.local_b[0, : len(cached)], [p.local_b for p in cached], atol=1e-12
        )


# -- Jacobians and effective masses ------------------------------------------------------------
def test_effective_mass_under_the_center_of_mass_is_the_body_mass():
    # a 2 kg box resting flat: each corner's normal row sees 1/m + (r x n) I^-1 (r x n); the
    # point straight below the COM has r x n = 0, so m_eff = m (split by the touching points)
    from engine.physics.reference.reference_solver import Bodies6, effective_mass

    inv_inertia = np.zeros((2, 3, 3))
    inv_inertia[1] = np.diag([3.0, 3.0, 3.0])
    bodies = Bodies6(np.zeros((2, 6)), np.array([0.0, 0.5]), inv_inertia)
    below = effective_mass(
        bodies, 0, 1, np.zeros(3), np.array([0.0, -0.1, 0.0]), np.array([0.0, 1.0, 0.0]), 1
    )
    assert below == pytest.approx(2.0, rel=1e-12)
    # a corner at r = (0.1, -0.1, 0.1): r x n = (0.1, 0, 0.1)... k = 0.5 + 3 (0.01 + 0.01)
    corner = effective_mass(
        bodies, 0, 1, np.zeros(3), np.array([-0.1, -0.1, 0.1]), np.array([0.0, 1.0, 0.0]), 4
    )
    assert corner == pytest.approx(1.0 / (4 * (0.5 + 3 * 0.02)), rel=1e-12)


def test_batched_jacobians_and_effective_masses_match_the_reference_build():
    from engine.physics.pipeline.solve_stage import gather_solver_input
    from engine.physics.reference.reference_solver import Bodies6, build_rows
    from engine.physics.solver.contact_batch import (
        ColorOrder,
        ManifoldPoints,
        PairCoefficients,
        SolverBodies,
        build_batch,
    )

    world = tumbling_world(0.5)
    b, store = world.bodies, world.manifolds
    moving = np.nonzero(b.body_awake[: b.count] & (b.body_motion_type[: b.count] == 2))[0]
    problem = gather_solver_input(b, store, moving, np.zeros((b.count, 6)))
    rows = problem.rows
    rotation = quat_to_matrix(b.body_rotation[: b.count])
    points_a, points_b, normals = store.world_points(rows, rotation, b.body_position[: b.count])
    counts = store.count[rows]
    normals = np.where((np.arange(4) >= counts[:, None])[..., None], [0, 1.0, 0], normals)
    pair = store.bodies[rows]
    batch = build_batch(
        ManifoldPoints(points_a, points_b, normals, counts, pair[:, 0], pair[:, 1]),
        SolverBodies(
            b.body_position[: b.count],
            problem.inv_mass,
            problem.inv_inertia,
            problem.approach_velocity,
        ),
        PairCoefficients(np.ones(len(rows)), np.zeros(len(rows)), store.impulse[rows]),
        ColorOrder(problem.color_slices),
        split_mass=True,
    )
    state = Bodies6(problem.velocity, problem.inv_mass, problem.inv_inertia)
    manifolds = build_rows(b, store, rows, state, state, world.settings)
    for m, manifold in enumerate(manifolds):
        for slot, point in enumerate(manifold.points):
            masses = [
                batch.normal_mass[m, slot],
                batch.tangent_mass[m, 2 * slot],
                batch.tangent_mass[m, 2 * slot + 1],
            ]
            np.testing.assert_allclose(point.masses, masses, rtol=1e-10)
            np.testing.assert_allclose(point.depth, batch.depth[m, slot], atol=1e-12)
            # J = [-n, -(r_a x n), n, r_b x n]: the reference's anchors rebuild the row
            n = point.directions[0]
            jacobian = np.concatenate([-n, -np.cross(point.r_a, n), n, np.cross(point.r_b, n)])
            np.testing.assert_allclose(batch.normal_jac[m, slot], jacobian, atol=1e-12)
    assert sum(len(m.points) for m in manifolds) > 10


# -- quaternion coefficient tables -------------------------------------------------------------
def test_quaternion_tables_match_engine_mn_formulas():
    rng = np.random.default_rng(2)
    for _ in range(20):
        q1, q2 = rng.normal(size=4), rng.normal(size=4)
        q1, q2 = q1 / np.linalg.norm(q1), q2 / np.linalg.norm(q2)
        m1, m2 = mn.Quaternion.from_xyzw(q1), mn.Quaternion.from_xyzw(q2)
        np.testing.assert_allclose(quat_to_matrix(q1), np.asarray(m1.to_matrix()), atol=1e-14)
        np.testing.assert_allclose(quat_multiply(q1, q2), (m1 * m2).xyzw, atol=1e-14)
        a, b = rng.normal(size=3), rng.normal(size=3)
        np.testing.assert_allclose(cross(a, b), np.cross(a, b), atol=1e-14)


@pytest.mark.parametrize("full_pass", [False, True])
def test_an_edge_job_on_the_stage_takes_fcls_points_with_its_first_triangles_normal(
    monkeypatch, full_pass
):
    """A cube standing on a corner 2.5 cm above the floor: no vertex within the stage's
    speculative distance (2 cm), but its probe (grown 2 cm along its axes, 3.5 cm at the
    corner) touches, so the stage-hull rule takes fcl's points (the edge pass, which
    reuses the first pass's outward normals, or with ``full_pass`` the second pass over
    fcl's triangles that it falls back to) and must agree with the per-pair reference."""
    world, templates = make_world()
    handle = register_primitive(templates, "cubeSolid", (0.1, 0.1, 0.1))
    corner_down = 0.1 * 3**0.5 + 0.025  # the lowest corner 2.5 cm above the floor
    body = add(world, templates, handle, [0.3, corner_down, 0.2])
    # turn the body diagonal (1, 1, 1) / sqrt(3) onto -y: axis (1, 1, 1) x (0, -1, 0)
    axis = np.array([1.0, 0.0, -1.0]) / 2**0.5
    angle = np.pi - np.arccos(1 / 3**0.5)
    q = np.concatenate([np.sin(angle / 2) * axis, [np.cos(angle / 2)]])
    body.rotation = mn.Quaternion.from_xyzw(q)
    pairs, rotation = candidate_pairs(world)
    edges = []  # the jobs the edge pass answered from the first pass's normals
    known_edge = batched_stage._known_edge
    monkeypatch.setattr(
        batched_stage,
        "_known_edge",
        lambda *args: edges.append(not full_pass and known_edge(*args)) or edges[-1],
    )
    assert pairs == [(0, body.object_id)]
    lowest = (rotation[1] @ np.array([1.0, 1.0, 1.0]) * 0.1)[1] + corner_down
    assert lowest == pytest.approx(0.025, abs=1e-9)  # the corner really points down
    position, point_a, point_b, normal, _ = narrow_phase(
        world.bodies, world.collision_objects, world.manifolds, pairs, rotation
    )
    reference = pair_contacts(
        world.bodies, world.collision_objects, world.manifolds, 0, 1, rotation
    )
    assert len(reference) == len(position) >= 1
    for contact, pa, pb, n in zip(reference, point_a, point_b, normal, strict=True):
        np.testing.assert_allclose(contact.point_a, pa, atol=1e-12)
        np.testing.assert_allclose(contact.point_b, pb, atol=1e-12)
        np.testing.assert_allclose(contact.normal, n, atol=1e-12)
    assert edges == [not full_pass]
    np.testing.assert_allclose(normal, [[0.0, 1.0, 0.0]] * len(normal), atol=1e-12)
    # a speculative gap no deeper than the corner's 2.5 cm (fcl's probe depth said +5.1 cm)
    depth = ((point_a - point_b) * normal).sum(axis=1)
    np.testing.assert_allclose(depth, -0.025, atol=1e-9)


def test_cube_falling_corner_down_onto_the_floor_never_rises():
    """The corner's probe touches the floor 3.5 cm early (the edge pass): its contact is a
    speculative gap, so the falling cube is not pushed up (it was, 1.6 cm in one step, when
    fcl's depth of the probe against the floor triangle was taken as the cube's)."""
    world, templates = make_world()
    handle = register_primitive(templates, "cubeSolid", (0.1, 0.1, 0.1))
    corner_down = 0.1 * 3**0.5
    body = add(world, templates, handle, [0.3, corner_down + 0.03, 0.2])
    axis = np.array([1.0, 0.0, -1.0]) / 2**0.5
    angle = np.pi - np.arccos(1 / 3**0.5)
    q = np.concatenate([np.sin(angle / 2) * axis, [np.cos(angle / 2)]])
    body.rotation = mn.Quaternion.from_xyzw(q)
    heights = [body.translation[1]]
    for _ in range(8):
        world.step_physics(1.0 / 60.0)
        heights.append(body.translation[1])
    assert np.all(np.diff(heights) <= 1e-9)
    assert heights[-1] == pytest.approx(corner_down, abs=3e-3)  # resting on its corner
