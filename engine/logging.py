"""``habitat_sim.logging``: rigidsim's log messages through the standard ``logging`` library.

Habitat-sim logs from C++ by *subsystem* (Default, Gfx, Scene, Sim, Physics, Nav, Metadata,
Geo, Io, ...) at one of four levels, chosen by the ``HABITAT_SIM_LOG`` environment variable,
and keeps a Python logger ``habitat_sim.logging.logger`` that prefixes ``[Sim]``. rigidsim has
no C++ side, so every message goes through Python's ``logging``:

* ``logger`` (name ``"rigidsim"``), Habitat's Python logger: level INFO, or ERROR when
  ``HABITAT_SIM_LOG`` makes the Default subsystem quiet; messages print as ``[Sim] ...``.
* ``get_logger("physics")`` and friends: the per-subsystem loggers ``rigidsim.<subsystem>``
  (children of ``logger``, so they share its handler), each at the level the filter string
  gives it, Habitat's default WARNING otherwise.

The filter string is Habitat's grammar, case-insensitive: ``level`` sets every subsystem,
``sub1,sub2=level`` sets some, commands are joined by ``:`` (``quiet:physics,sim=verbose``).
Levels: ``veryverbose`` (logging level 5), ``verbose``/``debug`` (DEBUG),
``default``/``warning`` (WARNING), ``quiet``/``error`` (ERROR). An unknown level or subsystem
raises ``ValueError`` naming it (Habitat aborts on it too).
"""

from __future__ import annotations

import logging
import os

__all__ = [
    "DEBUG",
    "ERROR",
    "FATAL",
    "INFO",
    "SUBSYSTEMS",
    "WARN",
    "WARNING",
    "configure",
    "get_logger",
    "logger",
    "parse_filter",
]

DEBUG = logging.DEBUG
INFO = logging.INFO
WARNING = logging.WARNING
WARN = logging.WARN
ERROR = logging.ERROR
FATAL = logging.FATAL

#: Habitat's log subsystems (esp::logging::Subsystem), lower case
SUBSYSTEMS = ("default", "gfx", "scene", "sim", "physics", "nav", "metadata", "geo", "io")
#: filter-string level name -> ``logging`` level
LEVELS = {
    "veryverbose": 5,
    "verbose": DEBUG,
    "debug": DEBUG,
    "default": WARNING,
    "warning": WARNING,
    "quiet": ERROR,
    "error": ERROR,
}
ENV_VAR = "HABITAT_SIM_LOG"


class HabitatSimFormatter(logging.Formatter):
    """Prefix every message with ``[Sim]`` as Habitat's Python logger does."""

    def format(self, record: logging.LogRecord) -> str:
        return "[Sim] " + super().format(record)


logger = logging.getLogger("rigidsim")
_handler = logging.StreamHandler()
_handler.setFormatter(HabitatSimFormatter())
logger.addHandler(_handler)
logger.propagate = False


def parse_filter(text: str) -> dict[str, int]:
    """Subsystem -> ``logging`` level for a ``HABITAT_SIM_LOG`` filter string.

    >>> parse_filter("quiet:physics,sim=verbose")["physics"] == DEBUG
    True
    """
    levels = dict.fromkeys(SUBSYSTEMS, WARNING)
    for command in filter(None, text.strip().lower().split(":")):
        names, _, level_name = command.rpartition("=")
        if level_name not in LEVELS:
            raise ValueError(
                f"{ENV_VAR}: unknown logging level {level_name!r} in {text!r}; "
                f"use one of {sorted(LEVELS)}"
            )
        targets = names.split(",") if names else list(SUBSYSTEMS)
        for name in targets:
            if name not in levels:
                raise ValueError(
                    f"{ENV_VAR}: unknown subsystem {name!r} in {text!r}; use one of {SUBSYSTEMS}"
                )
            levels[name] = LEVELS[level_name]
    return levels


def configure(text: str | None = None) -> dict[str, int]:
    """Set every logger's level from ``text`` (default: the ``HABITAT_SIM_LOG`` variable)."""
    levels = parse_filter(os.environ.get(ENV_VAR, "") if text is None else text)
    logger.setLevel(ERROR if levels["default"] >= ERROR else INFO)
    for name, level in levels.items():
        logging.getLogger(f"rigidsim.{name}").setLevel(level)
    return levels


def get_logger(subsystem: str = "default") -> logging.Logger:
    """The logger of one subsystem (``"physics"``, ``"sim"``, ...), ``rigidsim.<subsystem>``."""
    if subsystem not in SUBSYSTEMS:
        raise ValueError(f"unknown log subsystem {subsystem!r}; use one of {SUBSYSTEMS}")
    return logging.getLogger(f"rigidsim.{subsystem}")


configure()
