"""Wall-clock time per stage of the physics step, kept outside the stage functions.

``timer.run("collide", collision_stage, bodies, ...)`` calls the stage and adds its wall
time to ``timer.seconds["collide"]``, so ``World.step`` reads as a list of stage calls and
no stage carries timer bookkeeping. Stages that time their own sub-stages (the collision
stage times its broad phase) receive the timer as an explicit argument.
"""

from __future__ import annotations

import time
from collections import defaultdict
from collections.abc import Callable
from typing import Any, TypeVar

T = TypeVar("T")


class StageTimer:
    """Accumulated seconds per stage name (``seconds``: ``{name: s}``)."""

    def __init__(self) -> None:
        self.seconds: defaultdict[str, float] = defaultdict(float)

    def run(self, name: str, stage: Callable[..., T], *args: Any, **kwargs: Any) -> T:
        """Call ``stage(*args, **kwargs)`` and add its wall time to ``seconds[name]``."""
        start = time.perf_counter()
        result = stage(*args, **kwargs)
        self.seconds[name] += time.perf_counter() - start
        return result

    def reset(self) -> None:
        self.seconds.clear()
