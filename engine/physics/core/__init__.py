"""core: the data every stage of the physics step shares, and the math under it.

What is here, in reading order:

1. ``settings.py``: ``SolverSettings`` (the switches) and every tunable number with its unit;
   the conventions (Y up, meters, quaternions ``[x, y, z, w]``, normals from A to B).
2. ``bodies.py``: ``Bodies``, every body's state as ``body_<quantity>`` arrays (MuJoCo's
   ``mjData`` style), index 0 the stage; the motion-type codes.
3. ``motion_type.py``: Habitat's ``MotionType`` enum.
4. ``shapes.py``: collision shapes (python-fcl geometry plus the arrays of our own contacts).
5. ``quaternions.py``: batched unit-quaternion helpers.
6. ``reference_geometry.py``: plain 3-vector helpers and the ``Contact`` record of the
   per-pair code (read by both paths, so it lives here, not in ``reference/``).
7. ``profiling.py``: the wall-clock timer of each stage.
8. ``vectors.py``: ``dot`` and ``vecdot``, the short dot products of the collision
   kernels (NumPy 1.x and 2).

May import: nothing of ``engine.physics`` outside this folder (the lowest layer; see the
layering in :mod:`engine.physics`).
"""
