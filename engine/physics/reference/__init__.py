"""reference: the plain twins of the batched code, one pair or one contact point at a time.

``SolverSettings.use_vectorized = False`` sends the step through them; tests prove both paths
give the same contacts and the same poses (``tests/physics/test_reference_path.py``). Each
batched function names the twin it mirrors. Read a twin beside its batched module:

1. ``reference_pairs.py``: the pair table's rules for one shape pair (batched:
   ``collision/batched_pairs.py``, ``collision/batched_stage.py``);
2. ``reference_box_box.py``: one box pair (batched: ``collision/box_box.py``);
3. ``reference_manifolds.py``: one manifold's update (batched:
   ``collision/keyed_manifolds.py`` and ``collision/manifold_merge.py``);
4. ``reference_solver.py``: sequential impulses one point at a time (batched:
   ``solver/contact_batch.py``, ``solver/sequential_impulses.py``,
   ``solver/color_rows.py``, ``solver/stage_priority.py``);
5. ``reference_crossings.py``: a vertex's way out and the faces a hull crosses, and the
   prism test ``reference_pairs`` uses (batched: ``collision/stage_crossings.py``);
6. ``reference_soft.py``: the soft step one point at a time (batched:
   ``solver/soft_step.py``, with ``SolverSettings.soft_step``).

The runner of the reference collision stage, ``pipeline/reference_contacts.py``, sits with
the pair table it reads; the plain vector helpers are ``core/reference_geometry.py``.

May import: ``core``, ``collision``, ``solver``. Imported only by ``pipeline`` (where the
switch picks a path): the batched pieces never import a twin.
"""
