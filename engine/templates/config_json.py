"""Reading template config files: refuse what cannot be a file name or a shallow JSON object.

Shared by the templates (:mod:`engine.templates.attributes`), their managers and the scene dataset
reader (:mod:`engine.metadata`): :func:`checked_path` refuses non-strings, over-long text and
NUL characters before any file system call; :func:`read_json_object` refuses malformed JSON,
deep nesting (counted before parsing, in linear time) and top-level values that are not
objects, each with a ``ValueError`` naming the file.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

__all__ = ["MAX_JSON_DEPTH", "MAX_PATH_CHARS", "checked_path", "json_depth", "read_json_object"]


#: longest path string accepted (Linux PATH_MAX); longer text is not a file name
MAX_PATH_CHARS = 4096
#: deepest nesting of objects/arrays accepted in a config file (real configs nest < 10 deep)
MAX_JSON_DEPTH = 100


def checked_path(path: Any, name: str = "path") -> Path:
    """``path`` (a str or PathLike) as a ``Path``, refused up front when it cannot be a file
    name: not a string, longer than ``MAX_PATH_CHARS`` or holding a NUL character. The error
    names the length and the start of the text, never the whole (possibly huge) value."""
    if not isinstance(path, str | Path):
        raise TypeError(f"{name} must be a str or Path, got {type(path).__name__}")
    text = str(path)
    if len(text) > MAX_PATH_CHARS or "\0" in text:
        raise ValueError(
            f"{name} is not a file name: {len(text)} characters starting {text[:60]!r} "
            f"(at most {MAX_PATH_CHARS}, no NUL); pass the path of a config file or folder"
        )
    return Path(text)


def json_depth(text: str) -> int:
    """Deepest bracket nesting of JSON ``text`` (brackets inside strings count too, so this
    bounds the real depth from above); linear time, no recursion."""
    opens = text.count("{") + text.count("[")
    if opens <= MAX_JSON_DEPTH:
        return opens
    depth = deepest = 0
    for char in text:
        if char in "{[":
            depth += 1
            deepest = max(deepest, depth)
        elif char in "}]":
            depth -= 1
    return deepest


def read_json_object(path: Path) -> dict:
    """The JSON object in the file at ``path``; ``ValueError`` for malformed JSON, nesting
    deeper than ``MAX_JSON_DEPTH`` (refused before parsing) or any other top-level value."""
    text = path.read_text()
    if json_depth(text) > MAX_JSON_DEPTH:
        raise ValueError(
            f"{path} nests objects/arrays more than {MAX_JSON_DEPTH} deep; "
            f"a template config is a shallow JSON object"
        )
    try:
        data = json.loads(text)
    except json.JSONDecodeError as error:
        raise ValueError(f"malformed JSON in {path}: {error}") from error
    if not isinstance(data, dict):
        raise ValueError(f"{path} must hold a JSON object")
    return data
