"""The types every layer of the engine shares (the bottom of ``engine``, beside ``mn``).

What is here, in reading order:

1. :mod:`~engine.core.named_enum`: ``NamedIntEnum``, an integer enum that prints its name
   (``MotionType.DYNAMIC``), as Habitat's pybind11 enums do;
2. :mod:`~engine.core.fixed_fields`: ``FixedFields``, configuration classes whose misspelt
   attribute raises ``AttributeError`` as Habitat's C++ structs do;
3. :mod:`~engine.core.placeholder`: ``Placeholder``, the base of Habitat names rigidsim has
   no feature behind (articulated objects, Magnum's importers): they import and annotate,
   and raise ``NotImplementedError`` when used.

May import: the standard library only. Every folder of ``engine`` may import this one.
"""
