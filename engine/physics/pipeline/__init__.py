"""pipeline: the stages ``PhysicsWorld._step`` calls, each picking the batched path or its
reference twin (Bullet's ``CollisionDispatch``; the step itself is in ``world.py``).

What is here, in reading order:

1. ``collision_stage.py``: the collision stage (broad phase, box pre-test, contact cache,
   narrow phase and manifold update, stale manifolds);
2. ``pair_table.py``: the contact pair table, which rule makes the contacts of two shape
   kinds, with its batched function and its reference twin (``docs/contacts.md``);
3. ``narrow_phase.py``: the batched runner, every shape pair of a step to its rule, each
   rule's jobs at once;
4. ``reference_contacts.py``: the reference runner, one body pair at a time;
5. ``solve_stage.py``: the solve stage (gather the manifolds, color them, solve batched or
   by ``reference/reference_solver.py``).

May import: ``core``, ``collision``, ``solver``, ``reference``. Never ``objects`` or the
world: the stages are functions of explicit arrays and settings.
"""
