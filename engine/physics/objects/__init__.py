"""objects: Habitat's object API on top of the bodies (Jolt's ``Body`` interface,
Habitat's ``RigidObjectManager`` and ``ManagedRigidObject``).

What is here, in reading order:

1. ``rigid_object_manager.py``: ``RigidObjectManager`` (add, find, remove objects);
2. ``physics_object.py`` and ``object_properties.py``: ``ManagedPhysicsObject`` and its
   subclass ``ManagedRigidObject``, thin handles whose properties read and write the
   world's ``body_*`` arrays; ``object_checks.py``: their argument checks;
3. ``world_view.py``: ``WorldView``, the members of the world those handles use (a
   Protocol, so they never import ``world.py``);
4. ``body_builder.py``: a template to a body (meshes, collision shapes, mass properties);
   ``hull_sampling.py``: the capped, cached hull of a huge mesh; ``mass_ratio.py``: the
   warning beyond the mass ratio the solver holds;
5. ``node_sync.py``: body poses to scene nodes and user moves back;
6. ``velocity_control.py``: ``RigidState``, ``VelocityControl``; ``kinematic_motion.py``:
   the velocity of a kinematic body moved by its pose;
7. ``constraints.py``: Habitat's rigid constraints and their per-step solve;
   ``constraint_settings.py``: their settings and checks;
8. ``queries.py``: ray casts, contact tests, contact records, the state hash;
9. ``articulated.py``: Habitat's articulated-object names, placeholders (rigidsim has no
   articulated objects) that raise ``NotImplementedError`` when used.

May import: ``core`` (and ``engine.core``), ``collision``, ``solver``, ``pipeline``. Never
``world.py`` (the world imports them) and never ``reference``.
"""
