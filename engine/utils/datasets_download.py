"""Habitat's ``datasets_download`` command, answered from rigidsim's bundled demo data.

Habitat-sim downloads its test scenes and example objects with
``python -m habitat_sim.utils.datasets_download --uids habitat_test_scenes --data-path data/``
(its ``examples/demo_runner.py`` calls ``main(["--uids", "habitat_test_scenes"])`` when the
castle scene is missing). rigidsim downloads nothing: it links the matching pieces of its own
demo data (:func:`engine.demo.demo_data_path`) into Habitat's data layout, so a program that
expects ``data/scene_datasets/habitat-test-scenes/skokloster-castle.glb`` finds a scene there.

The uids it knows (each a *stand-in*, not Habitat's data):

- ``habitat_test_scenes``: the demo apartment (with its navmesh) under the names of Habitat's
  three test scenes (skokloster-castle, van-gogh-room, apartment_1);
- ``habitat_example_objects``: the demo objects (banana, cheezit, chefcan, largeclamp, mug)
  as ``objects/example_objects``;
- ``locobot_merged``: the demo locobot as ``objects/locobot_merged``.

Any other uid raises ``ValueError`` naming it before anything is written.
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from pathlib import Path

__all__ = ["STAND_IN_SOURCES", "install_stand_in", "main"]

#: uid -> ((path under data/, path under the demo data), ...); a path without a suffix links
#: both ``.glb`` and ``.navmesh``, one ending in ``/`` links a whole folder
STAND_IN_SOURCES: dict[str, tuple[tuple[str, str], ...]] = {
    "habitat_test_scenes": tuple(
        (f"scene_datasets/habitat-test-scenes/{name}", "scene_datasets/demo/apartment")
        for name in ("skokloster-castle", "van-gogh-room", "apartment_1")
    ),
    "habitat_example_objects": (("objects/example_objects/", "objects/example_objects/"),),
    "locobot_merged": (("objects/locobot_merged/", "objects/locobot_merged/"),),
}


def _link(link: Path, target: Path, replace: bool) -> None:
    """Make ``link`` point at ``target`` (keep an existing file unless ``replace``)."""
    if link.is_symlink() or link.exists():
        if not replace:
            return
        link.unlink()
    link.parent.mkdir(parents=True, exist_ok=True)
    link.symlink_to(target.resolve(), target_is_directory=target.is_dir())


def install_stand_in(uid: str, data_path: str | Path, replace: bool = False) -> list[Path]:
    """Link the demo data standing in for Habitat dataset ``uid`` under ``data_path``.

    Returns the links made (or kept). Raises ``ValueError`` for an unknown uid.
    """
    if uid not in STAND_IN_SOURCES:
        raise ValueError(
            f"unknown dataset uid {uid!r}: rigidsim downloads nothing and has stand-ins only for "
            f"{sorted(STAND_IN_SOURCES)}"
        )
    from engine.demo import demo_data_path

    demo = Path(demo_data_path())
    links = []
    for habitat_name, demo_name in STAND_IN_SOURCES[uid]:
        if habitat_name.endswith("/"):
            pairs = [(Path(data_path) / habitat_name.rstrip("/"), demo / demo_name.rstrip("/"))]
        else:
            pairs = [
                (Path(data_path) / (habitat_name + suffix), demo / (demo_name + suffix))
                for suffix in (".glb", ".navmesh")
            ]
        for link, target in pairs:
            _link(link, target, replace)
            links.append(link)
    return links


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="datasets_download", description="Link rigidsim's stand-ins for Habitat datasets."
    )
    group = parser.add_mutually_exclusive_group(required=True)
    group.add_argument("--uids", nargs="*", help="dataset uids to install")
    group.add_argument("--list", action="store_true", help="list the known uids")
    parser.add_argument("--data-path", default="data/", help="folder to install into")
    parser.add_argument("--replace", action="store_true", help="replace existing files")
    parser.add_argument("--no-replace", action="store_true", help="keep existing files")
    return parser


def main(args: Sequence[str] | None = None) -> None:
    """Command-line entry point taking Habitat's arguments (``--uids``, ``--data-path``, ...)."""
    options = _parser().parse_args(args)
    if options.list:
        for uid in sorted(STAND_IN_SOURCES):
            print(uid)
        return
    for uid in options.uids:  # refuse unknown uids before linking anything
        if uid not in STAND_IN_SOURCES:
            install_stand_in(uid, options.data_path)
    for uid in options.uids:
        links = install_stand_in(uid, options.data_path, replace=options.replace)
        print(f"{uid}: {len(links)} stand-in links under {options.data_path}")


if __name__ == "__main__":
    main()
