"""The vocabulary of the contact pair table: jobs, rules and the table that picks a rule.

Every shape pair of a step is a :class:`PairJob`. Which code makes its contacts depends only
on the two shapes' kinds (:class:`~shapes.ShapeKind`): a :class:`PairRule` names the kinds
it handles and holds two functions doing the same thing,

* ``batched(jobs, context, out) -> declined``: all of a step's jobs of that rule at once
  (NumPy arrays over the jobs), adding contacts to ``out`` (:class:`ContactBatch`);
* ``reference(job, context) -> contacts | None``: one job in plain loops, the version to
  read and step through; tests prove both give the same contacts.

A rule may *decline* a job (a box pair overlapping too deep for the clipping, say): the
batched function returns it, the reference function returns None, and the job goes to the
rule named ``fallback``. :class:`PairTable` resolves every kind pair to its first matching
rule once, like MuJoCo's collision-function table (``mjCOLLISIONFUNC``) or Box2D's
``b2AddType`` registry. Contacts are world ``point_a, point_b, normal`` with the normal from
A to B (:mod:`collide`); A is the shape of the lower body index (the stage is body 0).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from ..core.reference_geometry import Contact
from ..core.shapes import Shape, ShapeKind

_EMPTY = (
    np.zeros(0, dtype=np.int64),
    np.zeros((0, 3)),
    np.zeros((0, 3)),
    np.zeros((0, 3)),
    np.zeros(0, dtype=np.int64),
)

#: a contact's *key* names the features it comes from, unique inside its body pair (the
#: warm start of a feature-keyed manifold matches points by it, Box2D v3's contact ids):
#: ``shape_pair << SHAPE_PAIR_SHIFT | rule.order << RULE_SHIFT | feature`` with the shape
#: pair's index inside the body pair, the order of the rule that made it and the rule's
#: own feature number (a box corner, a hull vertex, a clipping candidate ...).
RULE_SHIFT, SHAPE_PAIR_SHIFT = 16, 24
#: the feature number of the i-th contact taken from fcl's records: ``FCL_FEATURE + i``
#: (apart from every vertex number of a hull)
FCL_FEATURE = 1 << 15


def contact_key(shape_pair: int, rule_order: int, feature: int) -> int:
    """The key of a contact (see :data:`RULE_SHIFT`), plain integers (reference path)."""
    return (shape_pair << SHAPE_PAIR_SHIFT) | (rule_order << RULE_SHIFT) | feature


class PairJob(NamedTuple):
    """One shape pair of the step: its sequence number (its place in the narrow phase's
    output order), each shape with its body index and fcl object, B's probe object (B grown
    by ``STAGE_SPECULATIVE_DISTANCE``, for stage pairs) and fcl's contact records of the
    pair, once a rule has asked fcl (empty before)."""

    seq: int
    shape_a: Shape
    body_a: int
    object_a: Any
    shape_b: Shape
    body_b: int
    object_b: Any
    probe_b: Any
    records: Sequence[Any] = ()


class JobColumns(NamedTuple):
    """The fields of a list of jobs as columns: ``columns.body_a[k] == jobs[k].body_a``."""

    seq: tuple[int, ...]
    shape_a: tuple[Shape, ...]
    body_a: tuple[int, ...]
    object_a: tuple[Any, ...]
    shape_b: tuple[Shape, ...]
    body_b: tuple[int, ...]
    object_b: tuple[Any, ...]
    probe_b: tuple[Any, ...]
    records: tuple[Sequence[Any], ...]


def job_columns(jobs: list[PairJob]) -> JobColumns:
    """``jobs`` (at least one) as :class:`JobColumns` (one transposition, no Python loop)."""
    return JobColumns(*zip(*jobs, strict=True))


@dataclass
class PairContext:
    """What a rule may read besides its jobs: the bodies, their fcl objects
    (``collision_objects.CollisionObjects``), the manifolds before this step's update (their
    cached normals keep a stage contact on its side) and every body's rotation matrix
    ``(n, 3, 3)``."""

    bodies: Any
    objects: Any
    store: Any
    rotation: np.ndarray

    def pose(self, body: int) -> tuple[np.ndarray, np.ndarray]:
        """``(R, x)``: body ``body``'s world_from_body rotation and position."""
        return self.rotation[body], self.bodies.body_position[body]


class ContactBatch:
    """Collects contact chunks tagged with (job sequence number, order inside the job) and
    each contact's feature number; ``rule_order`` is the order of the rule adding them
    (the narrow phase sets it before it calls a rule)."""

    def __init__(self) -> None:
        self.chunks: list[tuple] = []
        self.rule_order = 0

    def add(self, seq, local, point_a, point_b, normal, feature=None) -> None:
        """Contacts of jobs ``seq (k,)``, ``local (k,)`` their order inside each job,
        ``feature (k,)`` their feature numbers (default: ``local``)."""
        if len(seq):
            feature = local if feature is None else feature
            rule = self.rule_order << RULE_SHIFT
            self.chunks.append((seq, local, point_a, point_b, normal, feature + rule))

    def add_one(self, seq: int, result, first_feature: int = 0) -> None:
        """``result = (point_a, point_b, normal)`` arrays ``(k, 3)`` of job ``seq`` (or None),
        feature numbers ``first_feature + i``."""
        if result is not None and len(result[0]):
            k = len(result[0])
            local = np.arange(k)
            point_a, point_b, normal = result
            self.add(np.full(k, seq), local, point_a, point_b, normal, local + first_feature)

    def sorted(self, pair_of_seq: np.ndarray, first_seq: np.ndarray | None = None):
        """Flat ``(pair_position, point_a, point_b, normal, key)`` in sequence order;
        ``first_seq (p,)``: the first sequence number of every body pair (None: one shape
        pair each), for the keys' shape pair index (:data:`SHAPE_PAIR_SHIFT`)."""
        if not self.chunks:
            return _EMPTY
        seq, local, point_a, point_b, normal, key = (
            np.concatenate(part) for part in zip(*self.chunks, strict=True)
        )
        order = np.lexsort((local, seq))  # by shape pair, then by order inside the pair
        seq, key = seq[order], key[order]
        pair = pair_of_seq[seq]
        if first_seq is not None:
            key += (seq - first_seq[pair]) << SHAPE_PAIR_SHIFT
        return pair, point_a[order], point_b[order], normal[order], key


BatchedRule = Callable[[list[PairJob], PairContext, ContactBatch], list[PairJob]]
ReferenceRule = Callable[[PairJob, PairContext], "list[Contact] | None"]


@dataclass(frozen=True)
class PairRule:
    """One row of the pair table (see the module docstring).

    ``order``: rules are tried in ascending order, the first whose kinds match wins;
    ``either_order``: the rule also matches with A and B swapped (its functions then see
    the shapes in body order and turn the normal themselves); ``uses_fcl``: whether the
    rule asks python-fcl (the fcl objects of its bodies must be moved first);
    ``fallback``: the rule that takes the jobs this one declines.
    """

    order: int
    name: str
    kinds_a: frozenset[ShapeKind]
    kinds_b: frozenset[ShapeKind]
    batched: BatchedRule
    reference: ReferenceRule
    uses_fcl: bool
    fallback: str | None = None
    either_order: bool = False

    def matches(self, kind_a: ShapeKind, kind_b: ShapeKind) -> bool:
        """True when this rule handles a shape of ``kind_a`` (body A) with one of ``kind_b``."""
        if kind_a in self.kinds_a and kind_b in self.kinds_b:
            return True
        return self.either_order and kind_b in self.kinds_a and kind_a in self.kinds_b


class PairTable:
    """The rules, ordered, with every ``(kind_a, kind_b)`` resolved to its rule once."""

    def __init__(self, rules: list[PairRule]) -> None:
        self.rules = sorted(rules, key=lambda rule: rule.order)
        self.by_name = {rule.name: rule for rule in self.rules}
        if len(self.by_name) != len(rules) or len({r.order for r in rules}) != len(rules):
            raise ValueError("pair rules need distinct names and orders")
        for rule in self.rules:
            target = self.by_name.get(rule.fallback) if rule.fallback else rule
            if target is None or (rule.fallback and target.order <= rule.order):
                raise ValueError(
                    f"rule {rule.name!r}: fallback {rule.fallback!r} must be a later rule"
                )
        self.by_kinds: dict[tuple[ShapeKind, ShapeKind], PairRule] = {}
        for kind_a in ShapeKind:
            for kind_b in ShapeKind:
                matching = [r for r in self.rules if r.matches(kind_a, kind_b)]
                if matching:
                    self.by_kinds[(kind_a, kind_b)] = matching[0]
        self._fcl_free: dict[tuple[tuple[str, ...], tuple[str, ...]], bool] = {}

    def rule_for(self, kind_a: str, kind_b: str) -> PairRule:
        """The rule of a shape of ``kind_a`` (body A) against one of ``kind_b``."""
        try:
            return self.by_kinds[(kind_a, kind_b)]  # type: ignore[index]  # str == ShapeKind
        except KeyError:
            raise KeyError(f"no contact rule for shape kinds ({kind_a!r}, {kind_b!r})") from None

    def fallback_of(self, rule: PairRule) -> PairRule | None:
        """The rule that takes the jobs ``rule`` declines (None: declined jobs have none)."""
        return self.by_name[rule.fallback] if rule.fallback else None

    def needs_fcl(self, kinds_a: tuple[str, ...], kinds_b: tuple[str, ...]) -> bool:
        """Whether a body of shape kinds ``kinds_a`` against one of ``kinds_b`` asks fcl
        (some shape pair's rule uses it); declined jobs move their own objects."""
        key = (kinds_a, kinds_b)
        if key not in self._fcl_free:
            self._fcl_free[key] = all(
                not self.rule_for(a, b).uses_fcl for a in kinds_a for b in kinds_b
            )
        return not self._fcl_free[key]

    def markdown(self) -> str:
        """The table as Markdown: kind x kind -> rule name, then one row per rule."""
        kinds = list(ShapeKind)
        lines = [
            "| A \\ B | " + " | ".join(kind.value for kind in kinds) + " |",
            "|---" * (len(kinds) + 1) + "|",
        ]
        for kind_a in kinds:
            cells = [
                self.by_kinds[(kind_a, b)].name if (kind_a, b) in self.by_kinds else "-"
                for b in kinds
            ]
            lines.append(f"| **{kind_a.value}** | " + " | ".join(cells) + " |")
        lines += [
            "",
            "| order | rule | batched | reference | fcl? | declined jobs go to |",
            "|---|---|---|---|---|---|",
        ]
        for rule in self.rules:
            lines.append(
                f"| {rule.order} | {rule.name} | `{_qualified(rule.batched)}` | "
                f"`{_qualified(rule.reference)}` | {'yes' if rule.uses_fcl else 'no'} | "
                f"{rule.fallback or '-'} |"
            )
        return "\n".join(lines) + "\n"


def _qualified(function: Callable) -> str:
    """``module.function`` of a rule function (the module without its package)."""
    return f"{function.__module__.rsplit('.', 1)[-1]}.{function.__name__}"
