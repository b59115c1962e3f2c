"""Comparisons no reading can make true, found alike in YAML conditions and Python ones.

``range.distance_cm < 0`` (a distance sensor reads 0 or more) and ``range.distance_cm < 20 and
range.distance_cm > 30`` (where ``or`` was meant) would let a mission wait forever for
something that never comes. A YAML condition (:mod:`roboscript.mission.guards`) and a Python
condition method (:mod:`roboscript.mission.python_compiler`) are read by the same rule here:
each says which comparisons a condition makes of which readings, and :func:`never_true` says
whether they can ever hold together. Only what is certain is told: a reading compared with
anything but a plain number, or a number with its unit the caller converts, is left alone.
"""

from __future__ import annotations

import ast
from collections.abc import Callable, Iterable
from dataclasses import dataclass

__all__ = ["Bound", "NeverTrue", "bounds_of", "never_true"]

_FLIPPED: dict[type[ast.cmpop], ast.cmpop] = {
    ast.Lt: ast.Gt(),
    ast.LtE: ast.GtE(),
    ast.Gt: ast.Lt(),
    ast.GtE: ast.LtE(),
    ast.Eq: ast.Eq(),
}
"""A comparison read from its other side: ``20 > x`` is ``x < 20``."""
_BOUND: dict[type[ast.cmpop], str] = {
    ast.Lt: "<",
    ast.LtE: "<=",
    ast.Gt: ">",
    ast.GtE: ">=",
    ast.Eq: "==",
}
_WORDS = {
    "<": "below",
    "<=": "at most",
    ">": "above",
    ">=": "at least",
    "==": "equal to",
}
"""How a bound is said in a sentence."""

_DISTANCES = ("distance_cm", "distance_mm")
"""The ends of the names of a distance sensor's readings, which are never below 0."""


@dataclass(frozen=True)
class Bound:
    """One comparison of a reading with a number: ``reading word value`` (``x < 20``)."""

    value: float
    word: str
    node: ast.expr
    """The comparison it was read from (where to point)."""


@dataclass(frozen=True)
class NeverTrue:
    """Why comparisons made together can never hold, and where.

    Attributes:
        reading: The reading, as written (``range.distance_cm``).
        why: The reason, a sentence's end (``a distance sensor reads 0 or more, never below
            0``).
        node: The comparison to point at.
        apart: True when two bounds exclude each other (``x < 20 and x > 30``): 'or' may
            have been meant.
    """

    reading: str
    why: str
    node: ast.expr
    apart: bool

    def hint(self, written: str, parts: int) -> str | None:
        """What to write instead of the condition ``written`` (``parts`` comparisons joined
        by 'and'): two bounds that exclude each other joined by 'or' (told only for two, where
        'or' is surely what was meant); a distance the sensor can read."""
        if not self.apart:
            return f"compare with a distance it can read, e.g. {self.reading} < 20"
        if parts != 2:
            return None
        return f"to go when either holds, write or: {written.replace(' and ', ' or ').strip()}"


def _plain_number(node: ast.expr) -> float | None:
    """The number ``node`` is written as (``20``, ``-5``), or ``None`` for anything else."""
    sign = 1.0
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
        sign, node = -1.0, node.operand
    number = node.value if isinstance(node, ast.Constant) else None
    if isinstance(number, int | float) and not isinstance(number, bool):
        return sign * float(number)
    return None


def bounds_of(
    parts: Iterable[ast.expr],
    reading: Callable[[ast.expr], str | None],
    in_its_unit: Callable[[ast.expr, ast.expr], float | None] | None = None,
) -> dict[str, list[Bound]]:
    """The bounds that comparisons ``parts`` (all of which must hold) put on readings, by
    reading; ``reading(node)`` names what ``node`` reads (``range.distance_cm``), or gives
    ``None`` for what is no reading; ``in_its_unit(number, read)``, where given, is a number
    with its unit (``20 cm``) in the unit of the reading ``read``, or ``None``."""
    bounds: dict[str, list[Bound]] = {}
    for part in parts:
        if not isinstance(part, ast.Compare):
            continue
        items = [part.left, *part.comparators]
        for left, op, right in zip(items, part.ops, items[1:], strict=False):
            for read, number, sign in ((left, right, op), (right, left, _FLIPPED.get(type(op)))):
                value = _plain_number(number)
                if value is None and in_its_unit is not None:
                    value = in_its_unit(number, read)
                name = reading(read) if sign is not None and value is not None else None
                word = _BOUND.get(type(sign)) if sign is not None else None
                if name is not None and value is not None and word is not None:
                    bounds.setdefault(name, []).append(Bound(value, word, part))
    return bounds


def never_true(bounds: dict[str, list[Bound]]) -> NeverTrue | None:
    """Whether the ``bounds`` (from :func:`bounds_of`) can never hold together, and why."""
    for reading, limits in bounds.items():
        below = [b for b in limits if b.word in ("<", "<=", "==")]
        above = [b for b in limits if b.word in (">", ">=", "==")]
        if reading.endswith(_DISTANCES):
            for bound in below:
                if bound.value < 0 or (bound.value == 0 and bound.word == "<"):
                    return NeverTrue(
                        reading,
                        "a distance sensor reads 0 or more, never"
                        f" {_WORDS[bound.word]} {bound.value:g}",
                        bound.node,
                        apart=False,
                    )
        for high in below:
            for low in above:
                if low.value < high.value or (
                    low.value == high.value and "=" in low.word and "=" in high.word
                ):
                    continue
                return NeverTrue(
                    reading,
                    f"{reading} is never {_WORDS[high.word]} {high.value:g} and"
                    f" {_WORDS[low.word]} {low.value:g} at once",
                    high.node,
                    apart=True,
                )
    return None
