"""``turns``: which way the robot turns, how many times, how far each, how far in all."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from roboscript.angles import wrap_deg
from roboscript.grading.expectations.base import Rule, SpecContext
from roboscript.grading.expectations.words import at, by, deg, plural
from roboscript.grading.record import RunRecord, Verdict
from roboscript.inputs.fields import FieldReader
from roboscript.inputs.source import Mark

if TYPE_CHECKING:
    from typing_extensions import Self  # annotations only: Python 3.10 has no typing.Self

__all__ = [
    "DEFAULT_TURN_TOLERANCE_DEG",
    "MIN_TURN_DEG",
    "TURN_PAUSE_S",
    "TURN_RATE_DEG_S",
    "TURN_TRAVEL_MM",
    "Turn",
    "Turns",
    "find_turns",
]

DEFAULT_TURN_TOLERANCE_DEG = 20.0
TURN_RATE_DEG_S = 3.0
"""A robot turning faster than this is turning (driving straight, it drifts under 1°/s)."""
TURN_PAUSE_S = 0.2
"""Turning slower than :data:`TURN_RATE_DEG_S` for this long ends a stretch of turning, so the
wobble that settles a ``rotate`` belongs to its stretch."""
TURN_TRAVEL_MM = 20.0
"""Stretches of turning the same way with less travel than this between them are one turn:
two ``rotate: 45 deg`` in a row are one 90° corner, however long the robot paused between
them (a corner's sides are far longer)."""
MIN_TURN_DEG = 10.0
"""A turn smaller than this is a wobble (a steering correction), not a turn."""

Sample = tuple[float, float, float, float]


@dataclass(frozen=True)
class Turn:
    """One turn of a run: when it started and ended, and its angle (clockwise, right, > 0)."""

    start_s: float
    end_s: float
    angle_deg: float

    @property
    def direction(self) -> str:
        """``right`` (clockwise) or ``left``."""
        return "right" if self.angle_deg > 0 else "left"

    @property
    def text(self) -> str:
        """``91° right at 3.8 s``."""
        return f"{abs(self.angle_deg):.0f}° {self.direction} at {at(self.start_s)}"


def _unwrapped_headings(path: Sequence[Sample]) -> list[float]:
    """The path's headings, followed through north: 350° then 10° is 350° then 370°."""
    headings: list[float] = []
    for _, _, _, h in path:
        headings.append(h if not headings else headings[-1] + wrap_deg(h - headings[-1]))
    return headings


def find_turns(path: Sequence[Sample]) -> list[Turn]:
    """The turns of a path: where its heading keeps changing one way with no travel between.

    A stretch of turning starts when the robot turns faster than :data:`TURN_RATE_DEG_S` and
    ends once it has turned slower than that for :data:`TURN_PAUSE_S`. Stretches smaller than
    :data:`MIN_TURN_DEG` are wobbles and left out; consecutive stretches the same way with
    less than :data:`TURN_TRAVEL_MM` of travel between them are one turn. A turn's angle is
    how far the heading changed from its start to its end, clockwise (to the right) positive.
    """
    headings = _unwrapped_headings(path)
    stretches: list[tuple[int, int]] = []  # (first sample, last sample) of each stretch
    first: int | None = None  # the sample a stretch starts at
    last = 0  # its latest sample that ended a stretch of turning
    for i in range(1, len(path)):
        dt = path[i][0] - path[i - 1][0]
        if dt > 0 and abs(headings[i] - headings[i - 1]) / dt >= TURN_RATE_DEG_S:
            first = i - 1 if first is None else first
            last = i
        elif first is not None and path[i][0] - path[last][0] >= TURN_PAUSE_S - 1e-9:
            stretches.append((first, last))
            first = None
    if first is not None:
        stretches.append((first, last))
    turns: list[tuple[int, int]] = []
    for a, b in stretches:
        angle = headings[b] - headings[a]
        if abs(angle) < MIN_TURN_DEG:
            continue
        if turns:
            a0, b0 = turns[-1]
            same_way = (headings[b0] - headings[a0]) * angle > 0
            if same_way and _travel_mm(path, b0, a) < TURN_TRAVEL_MM:
                turns[-1] = (a0, b)
                continue
        turns.append((a, b))
    return [Turn(path[a][0], path[b][0], round(headings[b] - headings[a], 1)) for a, b in turns]


def _travel_mm(path: Sequence[Sample], a: int, b: int) -> float:
    """How far the centre moved along the path from sample ``a`` to sample ``b``."""
    return sum(
        math.hypot(path[i + 1][1] - path[i][1], path[i + 1][2] - path[i][2]) for i in range(a, b)
    )


@dataclass(frozen=True)
class Turns(Rule):
    """``turns``: which way the robot turns, how many times, how far each, how far in all.

    Angles are sizes (above 0); ``direction`` says which way. See :func:`find_turns` for
    what counts as one turn.
    """

    kind = "turns"

    direction: str | None = None
    count: int | None = None
    angle_deg: float | None = None
    total_deg: float | None = None
    tolerance_deg: float = DEFAULT_TURN_TOLERANCE_DEG

    @classmethod
    def parse(cls, reader: FieldReader, value: object, mark: Mark, ctx: SpecContext) -> Self:
        data = reader.mapping(value, "turns", mark)
        keys = ("direction", "count", "angle", "total", "tolerance")
        reader.allowed(data, keys, "turns")
        if not any(key in data for key in keys[:4]):
            raise reader.fail(
                "turns needs at least one of: direction, count, angle, total,"
                " such as {direction: right, count: 4, angle: 90 deg}",
                mark,
            )
        angles = {}
        for key in ("angle", "total"):
            if key in data:
                angles[key] = reader.quantity(data, key, "angle", "deg")
                if angles[key] <= 0:
                    raise reader.fail(
                        f"'{key}' is a size, more than 0;"
                        " say which way with direction: left or right",
                        data.value_mark(key),
                    )
        return cls(
            direction=(
                reader.choice(data, "direction", ("right", "left")) if "direction" in data else None
            ),
            count=reader.integer(data, "count") if "count" in data else None,
            angle_deg=angles.get("angle"),
            total_deg=angles.get("total"),
            tolerance_deg=(
                reader.positive(data, "tolerance", "angle", "deg")
                if "tolerance" in data
                else DEFAULT_TURN_TOLERANCE_DEG
            ),
        )

    def judge(self, record: RunRecord) -> Verdict:
        turns = find_turns(record.path)
        headings = _unwrapped_headings(record.path)
        net = headings[-1] - headings[0] if headings else 0.0
        tol = self.tolerance_deg
        parts: list[_Part] = []
        never = _Part(False, "the robot never turned")
        if self.direction is not None:
            wrong = [t for t in turns if t.direction != self.direction]
            if not turns:
                parts.append(never)
            elif wrong:
                worst = max(abs(t.angle_deg) for t in wrong)
                parts.append(
                    _Part(
                        False,
                        f"turned {wrong[0].text}; this test wants {self.direction} turns only",
                        -worst,
                        "deg",
                        None,
                        wrong[0].start_s,
                    )
                )
            else:
                parts.append(_Part(True))
        if self.count is not None:
            n, wanted = len(turns), self.count
            why = f"{plural(n, 'turn')}, expected {wanted}"
            when = turns[wanted].start_s if n > wanted else None  # too few has no moment
            short = float(wanted - n) if n > wanted else float(n - wanted) if n < wanted else None
            parts.append(_Part(n == wanted, why, short, "turns", None, when))
        if self.angle_deg is not None:
            if not turns:
                parts.append(never)
            else:
                errors = [abs(t.angle_deg) - self.angle_deg for t in turns]
                worst = max(range(len(turns)), key=lambda i: abs(errors[i]))
                margin = tol - abs(errors[worst])
                bad = next((i for i, e in enumerate(errors) if abs(e) > tol), worst)
                parts.append(
                    _Part(
                        margin >= 0,
                        f"turn {bad + 1} was {turns[bad].text}, expected {self.angle_deg:g}°"
                        f" ± {tol:g}°",
                        margin,
                        "deg",
                        margin / tol,
                        turns[bad].end_s if margin < 0 else None,
                    )
                )
        if self.total_deg is not None:
            sign = {"right": 1.0, "left": -1.0}.get(self.direction or "")
            error = net - sign * self.total_deg if sign else abs(net) - self.total_deg
            margin = tol - abs(error)
            way = "right" if net >= 0 else "left"
            wanted_way = f" {self.direction}" if self.direction else ""
            parts.append(
                _Part(
                    margin >= 0,
                    f"turned {abs(net):.0f}° {way} in all, expected {self.total_deg:g}°{wanted_way}"
                    f" ± {tol:g}°",
                    margin,
                    "deg",
                    margin / tol,
                    record.duration_s if margin < 0 else None,
                )
            )
        shown = ", ".join(t.text for t in turns[:6]) + (" ..." if len(turns) > 6 else "")
        seen = f"{plural(len(turns), 'turn')}" + (f" ({shown})" if turns else "")
        seen += f", {abs(net):.0f}° {'right' if net >= 0 else 'left'} in all"
        failed = [p for p in parts if not p.passed]
        if failed:
            part = failed[0]
            return Verdict(
                "turns",
                False,
                _turns_margin(part),
                part.when,
                f"{part.why}; {seen}" if turns else part.why,
                part.value,
                part.unit,
                part.relative,
            )
        measured = [p for p in parts if p.relative is not None]
        if not measured:
            return Verdict("turns", True, "", None, seen)
        part = min(measured, key=lambda p: p.relative if p.relative is not None else math.inf)
        return Verdict(
            "turns", True, _turns_margin(part), None, seen, part.value, part.unit, part.relative
        )


@dataclass(frozen=True)
class _Part:
    """One condition of a compound expectation, judged."""

    passed: bool
    why: str = ""
    value: float | None = None
    unit: str = ""
    relative: float | None = None
    when: float | None = None


def _turns_margin(part: _Part) -> str:
    if part.value is None:
        return ""
    if part.unit == "turns":
        return by(part.value, plural(int(abs(part.value)), "turn"))
    return by(part.value, deg(part.value))
