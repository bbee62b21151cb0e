"""collision: which bodies touch and where, as batched NumPy pieces (Bullet's
``BroadphaseCollision`` and ``NarrowPhaseCollision``, Jolt's ``Collision``).

What is here, in reading order (the collision stage that runs them is
:mod:`engine.physics.pipeline.collision_stage`):

1. broad phase: ``collision_groups.py`` (Habitat's groups and masks), ``collide.py`` (AABBs,
   sweep and prune, the oriented-box pre-test, round shapes on the stage),
   ``collision_objects.py`` (the fcl objects of every body), ``stage_grid.py`` (the stage
   triangles near each body);
2. contact rules, each for all pairs of its kind at once: ``pair_rules.py`` (jobs, rules:
   the vocabulary of the pair table), ``contact_helpers.py``, ``box_box.py`` (separating
   axes and clipping), ``batched_pairs.py``, ``batched_stage.py`` (hulls on the stage mesh),
   ``capsule_contacts.py`` (capsules and spheres, batched and per pair);
3. manifolds: ``contacts.py`` (``ManifoldStore``: up to four points per body pair, kept
   across steps), ``keyed_manifolds.py`` (fresh manifolds, ``feature_manifolds=True``: a
   step's points cut to four by feature keys, warm-started from the cached points),
   ``manifold_merge.py`` (the merge of fresh points into persistent manifolds: the
   default, and always for stage and capsule pairs), ``slot_choice.py`` (which points a
   row keeps: the supporting polygon, shared out in a corner of the stage),
   ``manifold_rows.py`` (a new row for a pair that first touches).

May import: ``core``. Never ``solver`` (the two are independent), ``reference``,
``pipeline``, ``objects`` or the world.
"""
