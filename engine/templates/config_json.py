"""Reading template config files: refuse what cannot be a file name or a shallow JSON object.

Shared by the templates (:mod:`engine.templates.attributes`), their managers and the scene dataset
reader (:mod:`engine.metadata`): :func:`checked_path` refuses non-strings, over-long text and
NUL characters before any file system call; :func:`read_json_object` refuses malformed JSON,
deep nesting (counted before parsing, in linear time), files larger than
``MAX_CONFIG_BYTES`` (refused from their size before anything is read, naming the string
field that runs past the first 64 KB when there is one) and top-level values that are not
objects, each with a ``ValueError`` naming the file.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

__all__ = [
    "MAX_CONFIG_BYTES",
    "MAX_JSON_DEPTH",
    "MAX_PATH_CHARS",
    "checked_path",
    "json_depth",
    "read_json_object",
]


#: longest path string accepted (Linux PATH_MAX); longer text is not a file name
MAX_PATH_CHARS = 4096
#: deepest nesting of objects/arrays accepted in a config file (real configs nest < 10 deep)
MAX_JSON_DEPTH = 100
#: largest config file read, bytes (Habitat's largest scene instance files are a few MB)
MAX_CONFIG_BYTES = 32 * 2**20
#: bytes read from the start of an over-large file to name the field that makes it large
_HEAD_BYTES = 64 * 2**10
#: ``"key": "`` (a string value opening), the last one in a file's head names the field
_STRING_FIELD = re.compile(r'"([^"\\]{1,200})"\s*:\s*"')


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
    size = path.stat().st_size
    if size > MAX_CONFIG_BYTES:
        raise ValueError(_too_large(path, size))
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


def _too_large(path: Path, size: int) -> str:
    """The message refusing a config file of ``size`` bytes, naming the string field that
    is still open at the end of the file's first ``_HEAD_BYTES`` (when there is one)."""
    with path.open("rb") as stream:
        head = stream.read(_HEAD_BYTES).decode("utf-8", errors="replace")
    opened = list(_STRING_FIELD.finditer(head))
    field = ""
    if opened and '"' not in head[opened[-1].end() :].replace('\\"', ""):
        field = f": field {opened[-1].group(1)!r} holds a string longer than {len(head)} bytes"
    return (
        f"{path} is {size / 2**20:.1f} MB{field}; a config file may be at most "
        f"{MAX_CONFIG_BYTES // 2**20} MB (MAX_CONFIG_BYTES) and a file name or handle at most "
        f"{MAX_PATH_CHARS} characters"
    )
