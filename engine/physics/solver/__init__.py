"""solver: velocities that respect the contacts, then the new poses and sleep (Bullet's
``ConstraintSolver`` and the integration half of ``Dynamics``).

What is here, in reading order (the solve stage that runs it is
:mod:`engine.physics.pipeline.solve_stage`; the doc page is ``docs/physics_solver.md``):

1. ``integrate.py``: semi-implicit Euler, forces to velocities and velocities to poses;
2. ``coloring.py``: graph colors, so one NumPy batch solves manifolds of distinct bodies;
3. ``contact_batch.py``: the contact rows (Jacobians, ``W = M^-1 J^T``, effective masses);
4. ``sequential_impulses.py``: the iterations (projected Gauss-Seidel over colors, warm
   starting, restitution, the split-impulse position solve), each color's normal and
   friction rows one fused update of ``color_rows.py``;
5. ``lumped_rows.py`` and ``stage_priority.py``: the push-only sweeps that let the stage
   have the last word;
6. ``rolling_friction.py``: rolling and spinning resistance;
7. ``sweep.py``: the swept test of fast bodies against static geometry;
8. ``sleeping.py``: islands fall asleep and wake.

May import: ``core``. Never ``collision`` (it reads manifolds as arrays, handed in by the
solve stage), ``reference``, ``pipeline``, ``objects`` or the world.
"""
