"""Habitat's ``utils.collect_env``: print what a bug report needs to know about this setup.

``python -m engine.utils.collect_env`` prints the Python version and platform, rigidsim's
version and build flags (:mod:`engine.bindings`: no Bullet library, rigidsim's own solver
stands in for it, no CUDA, no audio) and the versions of the packages rigidsim runs on.
"""

from __future__ import annotations

import platform
import sys
from importlib import metadata

__all__ = ["get_env_info", "main"]

#: the distributions rigidsim depends on (pyproject.toml), reported with their versions
PACKAGES = (
    "numpy",
    "scipy",
    "numpy-quaternion",
    "python-fcl",
    "trimesh",
    "matplotlib",
    "imageio",
    "pillow",
    "networkx",
    "tqdm",
)


def _version(distribution: str) -> str:
    try:
        return metadata.version(distribution)
    except metadata.PackageNotFoundError:
        return "not installed"


def get_env_info() -> dict[str, str]:
    """Name -> value of everything :func:`main` prints."""
    from engine import bindings

    info = {
        "Python": sys.version.split()[0],
        "Platform": platform.platform(),
        "rigidsim": _version("rigidsim"),
        "built_with_bullet": f"{bindings.built_with_bullet} (rigidsim's solver stands in)",
        "cuda_enabled": str(bindings.cuda_enabled),
        "audio_enabled": str(bindings.audio_enabled),
    }
    info.update({name: _version(name) for name in PACKAGES})
    return info


def main() -> None:
    """Print :func:`get_env_info`, one ``name: value`` per line."""
    for name, value in get_env_info().items():
        print(f"{name}: {value}")


if __name__ == "__main__":
    main()
