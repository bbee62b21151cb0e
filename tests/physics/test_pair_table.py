"""The contact pair table: every shape-kind pair has one rule, both narrow phases read it,
and the documentation shows the table the code uses."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from helpers import add, make_world, register_primitive, run
from test_capsule_contacts import CAPSULE, SPHERE
from test_manifolds_and_narrow_phase import candidate_pairs

from engine import mn
from engine.physics.collision.pair_rules import PairRule, PairTable
from engine.physics.core.shapes import ShapeKind
from engine.physics.pipeline.narrow_phase import narrow_phase
from engine.physics.pipeline.pair_table import PAIR_TABLE
from engine.physics.pipeline.reference_contacts import pair_contacts

DOCS = Path(__file__).resolve().parents[2] / "docs" / "contacts.md"


def test_every_body_shape_pair_has_exactly_one_rule():
    for kind_a in ShapeKind:
        for kind_b in ShapeKind:
            if kind_b == ShapeKind.MESH:  # the stage is body 0: always A, never B
                with pytest.raises(KeyError, match="mesh"):
                    PAIR_TABLE.rule_for(kind_a, kind_b)
                continue
            rule = PAIR_TABLE.rule_for(kind_a, kind_b)
            assert rule is PAIR_TABLE.rule_for(kind_a.value, kind_b.value)  # plain strings too
            if kind_a != ShapeKind.MESH:  # body pairs: the same rule in either order
                assert PAIR_TABLE.rule_for(kind_b, kind_a) is rule


def test_the_rules_of_each_kind_pair():
    expected = {
        ("mesh", "box"): "stage-hull",
        ("mesh", "capsule"): "stage-round",
        ("box", "box"): "box-box",
        ("box", "cone"): "hull-hull",
        ("sphere", "sphere"): "sphere-sphere",
        ("capsule", "capsule"): "capsule-capsule",
        ("sphere", "capsule"): "sphere-capsule",
        ("capsule", "sphere"): "sphere-capsule",
        ("capsule", "box"): "fcl",
    }
    for kinds, name in expected.items():
        assert PAIR_TABLE.rule_for(*kinds).name == name, kinds
    assert PAIR_TABLE.fallback_of(PAIR_TABLE.by_name["box-box"]).name == "hull-hull"


def test_bodies_of_analytic_rules_never_ask_fcl():
    assert not PAIR_TABLE.needs_fcl(("box",), ("box",))
    assert not PAIR_TABLE.needs_fcl(("capsule", "sphere"), ("capsule",))
    assert PAIR_TABLE.needs_fcl(("box",), ("box", "sphere"))
    assert PAIR_TABLE.needs_fcl(("cone",), ("cone",))


def test_a_fallback_must_be_a_later_rule():
    rule = PAIR_TABLE.by_name["box-box"]
    early = PairRule(5, "early", rule.kinds_a, rule.kinds_b, rule.batched, rule.reference, True)
    late = PairRule(50, "late", rule.kinds_a, rule.kinds_b, rule.batched, rule.reference, False)
    with pytest.raises(ValueError, match="early"):
        PairTable([PairRule(**{**rule.__dict__, "fallback": "early"}), early])
    with pytest.raises(ValueError, match="missing"):
        PairTable([PairRule(**{**rule.__dict__, "fallback": "missing"}), late])
    with pytest.raises(ValueError, match="distinct"):
        PairTable([rule, rule])


def test_the_documented_table_is_the_table_in_use():
    # after changing a rule, paste the output of
    #   python -c "from engine.physics.pipeline.pair_table import PAIR_TABLE;
    #   print(PAIR_TABLE.markdown())"
    # over the table in docs/contacts.md
    assert PAIR_TABLE.markdown() in DOCS.read_text(), "docs/contacts.md shows an old pair table"


def round_world():
    """Capsules, spheres and boxes tumbling onto each other and the floor."""
    world, templates = make_world()
    handles = [
        register_primitive(templates, CAPSULE, (0.1, 0.1, 0.1)),
        register_primitive(templates, SPHERE, (0.08, 0.08, 0.08)),
        register_primitive(templates, "cubeSolid", (0.08, 0.08, 0.08)),
        register_primitive(templates, CAPSULE, (0.06, 0.06, 0.06)),
    ]
    rng = np.random.default_rng(4)
    for k in range(12):
        body = add(
            world,
            templates,
            handles[k % 4],
            [0.2 * (k % 3) - 0.2, 0.15 + 0.2 * (k // 3), rng.uniform(-0.05, 0.05)],
        )
        q = rng.normal(size=4)
        body.rotation = mn.Quaternion.from_xyzw(q / np.linalg.norm(q))
    return world


@pytest.mark.parametrize("seconds", [0.3, 0.7])
def test_batched_round_contacts_match_the_per_pair_reference(seconds):
    world = round_world()
    run(world, seconds)
    pairs, rotation = candidate_pairs(world)
    position, point_a, point_b, normal, _ = narrow_phase(
        world.bodies, world.collision_objects, world.manifolds, pairs, rotation
    )
    rules_seen = set()
    for k, (a, c) in enumerate(pairs):
        for shape_a in world.bodies.shapes[a]:
            for shape_c in world.bodies.shapes[c]:
                rules_seen.add(PAIR_TABLE.rule_for(shape_a.kind, shape_c.kind).name)
        reference = pair_contacts(
            world.bodies, world.collision_objects, world.manifolds, a, c, rotation
        )
        mine = position == k
        assert len(reference) == mine.sum(), (a, c)
        for contact, pa, pb, n in zip(
            reference, point_a[mine], point_b[mine], normal[mine], strict=True
        ):
            np.testing.assert_allclose(contact.point_a, pa, atol=1e-12)
            np.testing.assert_allclose(contact.point_b, pb, atol=1e-12)
            np.testing.assert_allclose(contact.normal, n, atol=1e-12)
    assert {"capsule-capsule", "sphere-capsule", "stage-round"} <= rules_seen, rules_seen
