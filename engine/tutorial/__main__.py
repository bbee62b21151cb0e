"""``python -m engine.tutorial``: see :mod:`engine.tutorial.cli`."""

from engine.tutorial.cli import main

raise SystemExit(main())
