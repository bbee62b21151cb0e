"""Command line: ``python -m engine.viewer --demo-replay OUT.html [--seconds S]``.

Records the tutorial scene's replay (:mod:`engine.viewer.demo`) and writes the
self-contained HTML page (k3d inlined, no server, no network needed to view it).
"""

from __future__ import annotations

import argparse
import sys
import time

from engine.viewer.demo import DEMO_SECONDS, write_tutorial_replay


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m engine.viewer", description=__doc__)
    parser.add_argument(
        "--demo-replay",
        metavar="OUT.html",
        required=True,
        help="record the tutorial scene and write its replay page here",
    )
    parser.add_argument(
        "--seconds", type=float, default=DEMO_SECONDS, help="world seconds recorded"
    )
    args = parser.parse_args(argv)
    start = time.perf_counter()
    path = write_tutorial_replay(args.demo_replay, seconds=args.seconds)
    size_mb = path.stat().st_size / 1e6
    elapsed = time.perf_counter() - start
    print(f"wrote {path} ({size_mb:.1f} MB) in {elapsed:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
