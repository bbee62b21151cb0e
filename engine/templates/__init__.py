"""Templates and configuration: what objects, stages and the physics world are made from.

Habitat's paths for these are the thin faces ``engine.attributes``,
``engine.attributes_managers`` and ``engine.metadata``. What is here, in reading order:

1. :mod:`~engine.templates.config_json`: file names and JSON objects checked before use;
2. :mod:`~engine.templates.config_values`, :mod:`~engine.templates.user_config`: Habitat's
   typed key-value ``Configuration`` (``user_defined`` attributes);
3. :mod:`~engine.templates.base`: typed fields declared in a table, one validator;
4. :mod:`~engine.templates.primitive_attributes`: templates of the built-in primitives;
5. :mod:`~engine.templates.attributes`: object, stage and physics-manager templates;
6. :mod:`~engine.templates.managers`: template libraries (register, copy, lock, remove);
7. :mod:`~engine.templates.metadata`: scene datasets (``MetadataMediator``).

May import: ``engine.scene`` (primitive handles), ``engine.core``, ``engine.mn``,
``engine.logging``. Physics and the simulator read templates; templates never import them.
"""
