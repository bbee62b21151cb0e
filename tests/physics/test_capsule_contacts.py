"""Capsule contacts: the capsule-capsule and sphere-capsule rules against hand geometry,
fcl and their reference twin, and capsules resting where hand geometry says.

The unit ``capsule3DSolid`` (half length 0.75, radius 1) scaled 0.1 is a capsule of radius
r = 0.1 m around a 0.15 m axis: lying on the floor its axis is at y = r = 0.100, standing
its center is at y = 0.075 + 0.1 = 0.175.
"""

from __future__ import annotations

from types import SimpleNamespace

import fcl
import numpy as np
import pytest
from helpers import add, make_world, register_primitive, run

from engine import mn
from engine.physics.collision.capsule_contacts import capsule_pair, capsule_pair_batch
from engine.physics.collision.contact_helpers import segment_in_body
from engine.physics.collision.pair_rules import ContactBatch, PairContext, PairJob
from engine.physics.core import settings
from engine.physics.core.quaternions import quat_to_matrix
from engine.physics.core.shapes import primitive_shape

CAPSULE = (
    "capsule3DSolid_hemiRings_4_cylRings_1_segments_12_halfLen_0.75"
    "_useTexCoords_false_useTangents_false"
)
SPHERE = "icosphereSolid_subdivs_1"
LYING = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # body Y -> world X
ACROSS = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])  # body Y -> world Z


def capsule(radius=0.1):
    return primitive_shape(CAPSULE, np.full(3, radius), np.zeros(3))


def sphere(radius=0.08):
    return primitive_shape(SPHERE, np.full(3, radius), np.zeros(3))


def job_and_context(shape_a, pose_a, shape_b, pose_b):
    """One job of bodies 1 and 2 (fcl objects placed at the poses) and its context."""
    rotation = np.stack([np.eye(3), pose_a[0], pose_b[0]])
    position = np.stack([np.zeros(3), pose_a[1], pose_b[1]])
    objects = []
    for shape, (r, x) in ((shape_a, pose_a), (shape_b, pose_b)):
        obj = fcl.CollisionObject(shape.geometry, fcl.Transform())
        obj.setRotation(r @ shape.body_from_shape[:3, :3])
        obj.setTranslation(r @ shape.body_from_shape[:3, 3] + x)
        objects.append(obj)
    job = PairJob(0, shape_a, 1, objects[0], shape_b, 2, objects[1], None)
    bodies = SimpleNamespace(body_position=position)
    return job, PairContext(bodies, None, None, rotation)


def batched(jobs, context):
    out = ContactBatch()
    assert capsule_pair_batch(jobs, context, out) == []
    return out.sorted(np.zeros(len(jobs), dtype=np.int64))


def test_crossed_capsules_touch_at_their_axes_closest_points():
    # A lies along X at y = 0.1, B along Z above it at y = 0.28: 2 cm overlap at the origin
    job, context = job_and_context(
        capsule(), (LYING, np.array([0.0, 0.1, 0.0])), capsule(), (ACROSS, [0.0, 0.28, 0.0])
    )
    (contact,) = capsule_pair(job, context)
    np.testing.assert_allclose(contact.normal, [0, 1, 0], atol=1e-15)
    np.testing.assert_allclose(contact.point_a, [0, 0.2, 0], atol=1e-15)  # top of A
    np.testing.assert_allclose(contact.point_b, [0, 0.18, 0], atol=1e-15)  # bottom of B
    assert contact.depth == pytest.approx(0.02, abs=1e-15)


def test_parallel_capsules_touch_at_both_ends_of_their_overlap():
    # side by side along X, B shifted 0.05 along its axis: axes overlap on x in [-0.025, 0.075]
    job, context = job_and_context(
        capsule(), (LYING, np.zeros(3)), capsule(), (LYING, np.array([0.05, 0.195, 0.0]))
    )
    contacts = capsule_pair(job, context)
    assert len(contacts) == 2
    np.testing.assert_allclose(sorted(c.point_a[0] for c in contacts), [-0.025, 0.075], atol=1e-15)
    for contact in contacts:
        np.testing.assert_allclose(contact.normal, [0, 1, 0], atol=1e-15)
        assert contact.depth == pytest.approx(0.005, abs=1e-15)


def test_sphere_on_a_capsule_end_and_a_capsule_on_a_sphere():
    # sphere (r 0.08) above A's +X end cap, center 0.17 from the axis end: 1 cm overlap
    end = np.array([0.075, 0.0, 0.0])
    direction = np.array([0.6, 0.8, 0.0])
    for order in ("capsule first", "sphere first"):
        shapes = [
            (capsule(), (LYING, np.zeros(3))),
            (sphere(), (np.eye(3), end + 0.17 * direction)),
        ]
        if order == "sphere first":
            shapes.reverse()
        job, context = job_and_context(*shapes[0], *shapes[1])
        (contact,) = capsule_pair(job, context)
        sign = 1.0 if order == "capsule first" else -1.0
        np.testing.assert_allclose(contact.normal, sign * direction, atol=1e-15)
        assert contact.depth == pytest.approx(0.01, abs=1e-15)


def test_separated_beyond_the_speculative_distance_gives_no_contact():
    gap = settings.SPECULATIVE_DISTANCE + 1e-4
    job, context = job_and_context(
        capsule(), (LYING, np.zeros(3)), capsule(), (ACROSS, np.array([0.0, 0.2 + gap, 0.0]))
    )
    assert capsule_pair(job, context) == []


def random_jobs(count, seed):
    """Capsule-capsule and sphere-capsule jobs (both orders) at random overlapping poses."""
    rng = np.random.default_rng(seed)
    jobs = []
    for k in range(count):
        kinds = [(capsule(), capsule()), (sphere(), capsule()), (capsule(), sphere())][k % 3]
        q = rng.normal(size=(2, 4))
        rotation = quat_to_matrix(q / np.linalg.norm(q, axis=1, keepdims=True))
        offset = rng.normal(size=3) * 0.12
        jobs.append(
            job_and_context(kinds[0], (rotation[0], np.zeros(3)), kinds[1], (rotation[1], offset))
        )
    return jobs


def brute_force_depth(job, context):
    """r_a + r_b - the smallest distance of 2001 x 2001 points on the two axes."""
    ends = []
    for shape, body in ((job.shape_a, job.body_a), (job.shape_b, job.body_b)):
        start, end, radius = segment_in_body(shape)
        r, x = context.rotation[body], context.bodies.body_position[body]
        s = np.linspace(0.0, 1.0, 2001)[:, None]
        ends.append(((r @ start + x) * (1 - s) + (r @ end + x) * s, radius))
    (points_a, r_a), (points_b, r_b) = ends
    gap = np.inf
    for point in points_a[::20]:  # coarse on A, then refine around the best
        gap = min(gap, np.linalg.norm(points_b - point, axis=1).min())
    return r_a + r_b - gap


@pytest.mark.parametrize("seed", [1, 2])
def test_deepest_contact_matches_fcl_and_a_brute_force_distance(seed):
    checked = {"brute force": 0, "fcl": 0}
    for job, context in random_jobs(24, seed):
        contacts = capsule_pair(job, context)
        if not contacts:
            continue
        checked["brute force"] += 1
        deepest = max(contact.depth for contact in contacts)
        # the depth is r_a + r_b minus the axes' distance: a dense sampling of the axes
        assert deepest == pytest.approx(brute_force_depth(job, context), abs=2e-4)
        if "sphere" in (job.shape_a.kind, job.shape_b.kind):  # fcl's sphere-capsule is exact
            result = fcl.CollisionResult()
            request = fcl.CollisionRequest(num_max_contacts=4, enable_contact=True)
            if fcl.collide(job.object_a, job.object_b, request, result):
                record = result.contacts[0]
                assert deepest == pytest.approx(abs(record.penetration_depth), abs=1e-9)
                np.testing.assert_allclose(contacts[0].normal, record.normal, atol=1e-9)
                checked["fcl"] += 1
    assert checked["brute force"] >= 10 and checked["fcl"] >= 5, checked


def test_separated_capsules_match_fcl_distance(monkeypatch):
    # with a 1 m speculative distance every pair below has a contact: depth = -distance
    monkeypatch.setattr(settings, "SPECULATIVE_DISTANCE", 1.0)
    rng = np.random.default_rng(5)
    for _ in range(20):
        q = rng.normal(size=(2, 4))
        rotation = quat_to_matrix(q / np.linalg.norm(q, axis=1, keepdims=True))
        direction = rng.normal(size=3)
        offset = direction / np.linalg.norm(direction) * 0.45
        job, context = job_and_context(
            capsule(), (rotation[0], np.zeros(3)), capsule(), (rotation[1], offset)
        )
        distance = fcl.distance(
            job.object_a, job.object_b, fcl.DistanceRequest(), fcl.DistanceResult()
        )
        assert distance > 0.0
        contacts = capsule_pair(job, context)
        assert -max(c.depth for c in contacts) == pytest.approx(distance, abs=1e-6)


def test_batched_capsule_contacts_match_the_reference_twin():
    pairs = random_jobs(30, 3)
    # the parallel and crossed cases above too
    pairs.append(
        job_and_context(capsule(), (LYING, np.zeros(3)), capsule(), (LYING, [0.05, 0.195, 0.0]))
    )
    pairs.append(
        job_and_context(capsule(), (LYING, np.zeros(3)), capsule(), (ACROSS, [0.0, 0.18, 0.0]))
    )
    for job, context in pairs:
        reference = capsule_pair(job, context)
        _, point_a, point_b, normal, _ = batched([job], context)
        assert len(reference) == len(point_a)
        for contact, pa, pb, n in zip(reference, point_a, point_b, normal, strict=True):
            np.testing.assert_allclose(contact.point_a, pa, atol=1e-12)
            np.testing.assert_allclose(contact.point_b, pb, atol=1e-12)
            np.testing.assert_allclose(contact.normal, n, atol=1e-12)


@pytest.mark.parametrize("vectorized", [True, False])
def test_capsules_rest_where_hand_geometry_says(vectorized):
    world, templates = make_world()
    world.settings.use_vectorized = vectorized
    handle = register_primitive(templates, CAPSULE, (0.1, 0.1, 0.1))
    lying_rotation = mn.Quaternion.rotation(mn.Rad(np.pi / 2), mn.Vector3(0, 0, 1))
    across_rotation = mn.Quaternion.rotation(mn.Rad(np.pi / 2), mn.Vector3(1, 0, 0))
    lying = add(world, templates, handle, [0.0, 0.2, 0.0])
    lying.rotation = lying_rotation
    standing = add(world, templates, handle, [1.0, 0.25, 0.0])
    bottom = add(world, templates, handle, [2.0, 0.2, 0.0])
    bottom.rotation = lying_rotation
    top = add(world, templates, handle, [2.0, 0.45, 0.0])  # crossed on the bottom one
    top.rotation = across_rotation
    ball = register_primitive(templates, SPHERE, (0.05, 0.05, 0.05))
    add(world, templates, ball, [3.0, 0.2, 0.0])
    on_ball = add(world, templates, handle, [3.0, 0.45, 0.0])
    on_ball.rotation = lying_rotation
    run(world, 2.0)
    slop = settings.PENETRATION_SLOP  # resting overlaps stay within the solver's slop
    assert lying.translation[1] == pytest.approx(0.100, abs=slop)  # axis at y = r
    assert standing.translation[1] == pytest.approx(0.175, abs=slop)  # 0.075 + r
    assert bottom.translation[1] == pytest.approx(0.100, abs=slop)
    assert top.translation[1] == pytest.approx(0.300, abs=2 * slop)  # r + 2 r
    assert on_ball.translation[1] == pytest.approx(0.200, abs=2 * slop)  # 2 r_ball + r
