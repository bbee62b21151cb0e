"""Count the NumPy operations Python code issues, by bytecode tracing: a noise-free work budget.

On a loaded, shared machine a step's time varies by 2x between runs; the number of NumPy
operations it issues does not. A pure-NumPy step costs about (operations) x (NumPy's per-call
floor, 0.35-1.8 us), so that count is what a faster step has to shrink.

What counts (one each), executed in a *counted frame* (a Python frame whose code file lies
under one of ``roots``, by default the repository's ``engine/``, ``render/`` and ``navmesh/``):

* **call**: a call (``CALL``, ``CALL_FUNCTION_EX``) whose callable is NumPy's: a ufunc, an
  object whose ``__module__`` starts with ``numpy`` (``np.where``, ``np.linalg.norm``,
  ``np.float64``), or a method of a NumPy object (``a.sum()``, ``np.add.at``, a
  ``Generator``'s ``normal``);
* **operator**: a binary or in-place operator (``BINARY_OP``), a comparison (``COMPARE_OP``)
  or a unary ``-``, ``+``, ``~`` with an ndarray or NumPy scalar (``np.generic``) operand;
* **subscript**: ``x[key]`` (``BINARY_SUBSCR``, ``BINARY_SLICE``) on an ndarray or NumPy
  scalar;
* **store**: ``x[key] = value`` (``STORE_SUBSCR``, ``STORE_SLICE``) into an ndarray.

Not counted: attribute reads (``a.shape``, ``a.T``), ``len``, iteration over an array,
conversions by Python builtins (``float(a)``), anything inside NumPy's own Python code (a call
into ``np.linalg.norm`` counts one, whatever it runs inside) and work in uncounted frames. The
count is deterministic: the same code on the same inputs gives the same number on every run
and machine (for one Python and NumPy version).

How: ``sys.settrace`` with ``frame.f_trace_opcodes = True`` (CPython 3.11 and 3.12; on 3.12
``settrace`` runs on ``sys.monitoring``) sees each instruction before it runs; the operands
are read from the frame's value stack (CPython's ``_PyInterpreterFrame``: ``localsplus``
holds the locals, then the stack, ``stacktop`` past its top), a layout checked against
``frame.f_code`` on every counted frame, so a Python whose layout differs raises instead of
counting wrongly.
"""

from __future__ import annotations

import ctypes
import dis
import sys
from collections import Counter
from pathlib import Path
from types import CodeType, FrameType

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_ROOTS = tuple(str(ROOT / name) for name in ("engine", "render", "navmesh"))
KINDS = ("call", "operator", "subscript", "store")

# (offset of _PyInterpreterFrame* in PyFrameObject, of f_code in it, of stacktop, of localsplus)
_LAYOUTS = {(3, 11): (24, 32, 64, 72), (3, 12): (24, 0, 64, 72)}
# opcode name -> (kind, how to find the operands: "binary", "unary", "subscr", ...)
_OPCODES = {
    "BINARY_OP": ("operator", "binary"),
    "COMPARE_OP": ("operator", "binary"),
    "UNARY_NEGATIVE": ("operator", "unary"),
    "UNARY_POSITIVE": ("operator", "unary"),
    "UNARY_INVERT": ("operator", "unary"),
    "BINARY_SUBSCR": ("subscript", "subscr"),
    "BINARY_SLICE": ("subscript", "slice"),
    "STORE_SUBSCR": ("store", "store"),
    "STORE_SLICE": ("store", "store_slice"),
    "CALL": ("call", "call"),
    "CALL_FUNCTION_EX": ("call", "call_ex"),
}
_NUMPY_VALUES = (np.ndarray, np.generic)


def _is_numpy_callable(function, bound_self) -> bool:
    """Whether calling ``function`` (with ``bound_self`` for a method call) is NumPy's."""
    if isinstance(function, np.ufunc):
        return True
    owner = bound_self if bound_self is not None else getattr(function, "__self__", None)
    if owner is not None and type(owner).__module__.startswith("numpy"):
        return True
    module = getattr(function, "__module__", None)
    return isinstance(module, str) and module.startswith("numpy")


class OpCounter:
    """Context manager counting NumPy operations (module docstring) in counted frames.

    ``counts`` holds the totals by kind, ``by_function`` by ``(file name, qualified name)``;
    ``total`` is their sum. ``instructions`` counts every bytecode instruction executed in
    counted frames, NumPy's or not (pure-Python work such as a loop over dicts shows there,
    not in ``total``), ``instructions_by_code`` the same per code object (see
    :meth:`instructions_by_function`). Tracing replaces any other trace function while active.
    """

    def __init__(self, roots: tuple[str, ...] = DEFAULT_ROOTS) -> None:
        layout = _LAYOUTS.get(sys.version_info[:2])
        if layout is None:
            raise RuntimeError(
                f"OpCounter reads CPython's frame layout of Python 3.11 or 3.12, not "
                f"{sys.version.split()[0]}"
            )
        self._frame_at, self._code_at, self._stacktop_at, self._locals_at = layout
        self.roots = tuple(str(Path(r)) for r in roots)
        self.counts: Counter[str] = Counter()
        self.by_function: Counter[tuple[str, str]] = Counter()
        self.instructions = 0
        self.instructions_by_code: Counter[CodeType] = Counter()
        self._tables: dict[CodeType, list | None] = {}
        self._saved = None

    @property
    def total(self) -> int:
        return sum(self.counts.values())

    def reset(self) -> None:
        self.counts.clear()
        self.by_function.clear()
        self.instructions = 0
        self.instructions_by_code.clear()

    def instructions_by_function(self) -> Counter[tuple[str, str]]:
        """Bytecode instructions executed, by ``(file name, qualified name)``."""
        out: Counter[tuple[str, str]] = Counter()
        for code, count in self.instructions_by_code.items():
            out[(Path(code.co_filename).name, code.co_qualname)] += count
        return out

    def __enter__(self) -> OpCounter:
        self._saved = sys.gettrace()
        sys.settrace(self._on_call)
        return self

    def __exit__(self, *exc) -> None:
        sys.settrace(self._saved)

    # --- tracing -------------------------------------------------------------------------
    def _table(self, code: CodeType) -> list | None:
        """Per instruction slot (offset // 2): ``(kind, operands, oparg)`` or None; None for
        a code object outside the roots."""
        if code not in self._tables:
            table = None
            if code.co_filename.startswith(self.roots):
                table = [None] * (len(code.co_code) // 2)
                for ins in dis.get_instructions(code):
                    if ins.opname in _OPCODES:
                        table[ins.offset // 2] = (*_OPCODES[ins.opname], ins.arg or 0)
            self._tables[code] = table
        return self._tables[code]

    def _on_call(self, frame: FrameType, event: str, arg):
        if event != "call" or self._table(frame.f_code) is None:
            return None
        self._check_layout(frame)
        frame.f_trace_lines = False
        frame.f_trace_opcodes = True
        return self._on_opcode

    def _check_layout(self, frame: FrameType) -> None:
        interpreter_frame = ctypes.c_void_p.from_address(id(frame) + self._frame_at).value
        code = ctypes.c_void_p.from_address(interpreter_frame + self._code_at).value
        if code != id(frame.f_code):
            raise RuntimeError("OpCounter: this CPython's frame layout is not the one expected")

    def _stack(self, frame: FrameType, depth: int) -> list:
        """The top ``depth`` values of the frame's value stack, deepest first (None for a
        NULL slot)."""
        base = ctypes.c_void_p.from_address(id(frame) + self._frame_at).value
        top = ctypes.c_int.from_address(base + self._stacktop_at).value
        values = []
        for slot in range(top - depth, top):
            pointer = ctypes.c_void_p.from_address(base + self._locals_at + 8 * slot).value
            values.append(None if pointer is None else ctypes.cast(pointer, ctypes.py_object).value)
        return values

    def _on_opcode(self, frame: FrameType, event: str, arg):
        if event != "opcode":
            return self._on_opcode
        code = frame.f_code
        self.instructions += 1
        self.instructions_by_code[code] += 1
        entry = self._tables[code][frame.f_lasti // 2]
        if entry is not None and self._counts(frame, entry[1], entry[2]):
            self.counts[entry[0]] += 1
            self.by_function[(Path(code.co_filename).name, code.co_qualname)] += 1
        return self._on_opcode

    def _counts(self, frame: FrameType, operands: str, oparg: int) -> bool:
        """Whether the instruction about to run is a NumPy operation (module docstring)."""
        if operands == "binary":
            return any(isinstance(v, _NUMPY_VALUES) for v in self._stack(frame, 2))
        if operands == "unary":
            return isinstance(self._stack(frame, 1)[0], _NUMPY_VALUES)
        if operands in ("subscr", "store", "slice", "store_slice"):
            depth = {"subscr": 2, "store": 2, "slice": 3, "store_slice": 3}[operands]
            return isinstance(self._stack(frame, depth)[0], _NUMPY_VALUES)
        if operands == "call":
            first, second = self._stack(frame, oparg + 2)[:2]
            return (
                _is_numpy_callable(second, None)
                if first is None
                else (_is_numpy_callable(first, second))
            )
        # CALL_FUNCTION_EX: [NULL, callable, args, (kwargs)]
        return _is_numpy_callable(self._stack(frame, 2 + (oparg & 1))[0], None)
