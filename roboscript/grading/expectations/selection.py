"""Which stretches of a run an expectation judges, decided from what the robot did.

A spec selects by the world's record: ``during: whole run`` (the default), a time window
``during: {from: 5 s, to: 20 s}`` on the mission clock, a stretch of the path
``along: {from: 50 cm, to: 2.5 m}`` (distance the robot's centre travelled since the start),
or ``in_region: corridor`` (while the robot's centre is inside a world region). Given
together, they all must hold. ``state: follow`` selects by the mission's own account of its
states instead: a robot can name any stretch ``follow``, so the shipped tests judge by the
world.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from itertools import pairwise

from roboscript.errors import did_you_mean
from roboscript.grading.expectations.base import SpecContext
from roboscript.grading.expectations.regions import read_region_names, world_regions
from roboscript.grading.expectations.words import at, cm
from roboscript.grading.record import RunRecord
from roboscript.grading.regions import dense_path
from roboscript.inputs.fields import FieldReader
from roboscript.inputs.source import Mark, YamlMap

__all__ = ["DEFAULT_SETTLE_S", "SELECTION_KEYS", "WHOLE_RUN", "Selection"]

DEFAULT_SETTLE_S = 1.0
WHOLE_RUN = "whole run"
SELECTION_KEYS = ("during", "along", "in_region", "state", "settle")
"""The keys of an expectation's mapping that say which stretches of a run it judges."""

Span = tuple[float, float]
"""A stretch of the mission clock, ``[start_s, end_s)``."""


@dataclass(frozen=True)
class Selection:
    """Which moments of a run are judged: where all the given selectors hold, less the first
    ``settle_s`` of each selected stretch.

    Attributes:
        from_s: A time window's start on the mission clock (``during``), or ``None``.
        to_s: A time window's end, or ``None``.
        from_mm: Where a stretch of the path starts (``along``): distance travelled, or ``None``.
        to_mm: Where it ends, or ``None``.
        regions: World regions the robot's centre must be inside (any of them), or none.
        state: A state the mission says it is in (its own account), or ``None``.
        settle_s: Time at the start of each selected stretch that is not judged.
    """

    from_s: float | None = None
    to_s: float | None = None
    from_mm: float | None = None
    to_mm: float | None = None
    regions: tuple[str, ...] = ()
    state: str | None = None
    settle_s: float = DEFAULT_SETTLE_S

    @classmethod
    def parse(cls, reader: FieldReader, data: YamlMap, ctx: SpecContext) -> Selection:
        """The selectors among ``data``'s keys (see :data:`SELECTION_KEYS`)."""
        window: tuple[float | None, float | None] = (None, None)
        if "during" in data:
            window = _window(reader, data)
        stretch: tuple[float | None, float | None] = (None, None)
        if "along" in data:
            stretch = _range(
                reader,
                data["along"],
                data.value_mark("along"),
                "along",
                ("distance", "mm"),
                "such as along: {from: 50 cm, to: 2.5 m}",
            )
        settle = DEFAULT_SETTLE_S
        if "settle" in data:
            settle = reader.quantity(data, "settle", "time", "s")
            if settle < 0:
                raise reader.fail("settle cannot be negative", data.value_mark("settle"))
        return cls(
            from_s=window[0],
            to_s=window[1],
            from_mm=stretch[0],
            to_mm=stretch[1],
            regions=(
                read_region_names(
                    reader, data["in_region"], data.value_mark("in_region"), ctx, "in_region"
                )
                if "in_region" in data
                else ()
            ),
            state=reader.text(data, "state") if "state" in data else None,
            settle_s=settle,
        )

    @property
    def text(self) -> str:
        """The stretches in words: ``in 'follow'``, ``over the whole run``, ``inside 'hall'``..."""
        parts = []
        if self.state is not None:
            parts.append(f"in '{self.state}'")
        if self.from_s is not None or self.to_s is not None:
            parts.append(_between(self.from_s, self.to_s, at))
        if self.from_mm is not None or self.to_mm is not None:
            parts.append(_between(self.from_mm, self.to_mm, cm) + " along its path")
        if self.regions:
            parts.append("inside " + " or ".join(f"'{name}'" for name in self.regions))
        return ", ".join(parts) or "over the whole run"

    def spans(self, record: RunRecord) -> list[Span]:
        """The stretches of ``record`` where every selector holds (settling not taken off)."""
        spans: list[Span] = [(0.0, math.inf)]
        if self.state is not None:
            spans = _overlap(
                spans, [(a, b) for a, b, name in record.state_intervals() if name == self.state]
            )
        if self.from_s is not None or self.to_s is not None:
            window = (self.from_s or 0.0, math.inf if self.to_s is None else self.to_s)
            spans = _overlap(spans, [window])
        if self.from_mm is not None or self.to_mm is not None:
            spans = _overlap(spans, [_along(record, self.from_mm, self.to_mm)])
        if self.regions:
            spans = _overlap(spans, _inside(record, self.regions))
        return [(a, b) for a, b in spans if b > a]

    def judged(self, t_s: float, spans: list[Span]) -> bool:
        """Whether a moment is judged: in a span, after the span's first ``settle_s``."""
        return any(a + self.settle_s <= t_s < b for a, b in spans)

    def never(self, record: RunRecord) -> str | None:
        """Why no part of ``record`` is selected, in one sentence, when a selector was never
        met at all (``None``: they were, but not long enough to settle)."""
        if self.state is not None and all(name != self.state for _, name in record.states):
            return f"the mission never entered state '{self.state}'"
        if self.from_s is not None and record.duration_s <= self.from_s:
            return f"the run ended at {at(record.duration_s)}, before {at(self.from_s)}"
        if self.from_mm is not None and _travelled(record)[-1] < self.from_mm:
            return (
                f"the robot travelled {cm(_travelled(record)[-1])} in all, never {cm(self.from_mm)}"
            )
        if self.state is None and record.duration_s < (self.from_s or 0.0) + self.settle_s:
            return (
                f"the run ended at {at(record.duration_s)}, before the {self.settle_s:g} s it is"
                " given to settle were over"
            )
        if self.regions and not _inside(record, self.regions):
            names = " or ".join(f"'{name}'" for name in self.regions)
            return f"the robot never entered {names}"
        return None


def _between(low: float | None, high: float | None, show: Callable[[float], str]) -> str:
    if low is not None and high is not None:
        return f"from {show(low)} to {show(high)}"
    if low is not None:
        return f"from {show(low)} on"
    return f"until {show(high or 0.0)}"


def _window(reader: FieldReader, data: YamlMap) -> tuple[float | None, float | None]:
    value, mark = data["during"], data.value_mark("during")
    example = f"'{WHOLE_RUN}' or a time window such as during: {{from: 5 s, to: 20 s}}"
    if isinstance(value, str):
        if value.strip() != WHOLE_RUN:
            raise reader.fail(
                f"during is {example} (got '{value}')",
                mark,
                did_you_mean(value, (WHOLE_RUN,)),
            )
        return None, None
    return _range(reader, value, mark, "during", ("time", "s"), example)


def _range(
    reader: FieldReader,
    value: object,
    mark: Mark,
    key: str,
    dimension: tuple[str, str],
    example: str,
) -> tuple[float | None, float | None]:
    """``{from: A, to: B}`` (either may be left out) in ``dimension``; ``from`` before ``to``."""
    if not isinstance(value, YamlMap):
        raise reader.fail(f"{key} is {example}", mark)
    reader.allowed(value, ("from", "to"), key)
    if not value:
        raise reader.fail(f"{key} needs from, to or both, {example}", mark)
    ends = {}
    for end in ("from", "to"):
        if end in value:
            ends[end] = reader.quantity(value, end, *dimension)
            if ends[end] < 0:
                raise reader.fail(f"'{end}' cannot be negative", value.value_mark(end))
    if "from" in ends and "to" in ends and ends["from"] >= ends["to"]:
        raise reader.fail("'from' must come before 'to'", value.value_mark("to"))
    return ends.get("from"), ends.get("to")


def _overlap(first: list[Span], second: list[Span]) -> list[Span]:
    """Where a span of ``first`` and one of ``second`` overlap."""
    return [(max(a, c), min(b, d)) for a, b in first for c, d in second if max(a, c) < min(b, d)]


def _travelled(record: RunRecord) -> list[float]:
    """Distance the centre had travelled at each path sample, millimetres."""
    total = [0.0]
    for (_, x0, y0, _), (_, x1, y1, _) in pairwise(record.path):
        total.append(total[-1] + math.hypot(x1 - x0, y1 - y0))
    return total


def _along(record: RunRecord, from_mm: float | None, to_mm: float | None) -> Span:
    """When the robot had first travelled ``from_mm`` and ``to_mm`` (interpolated between
    samples); the end of time when it never travelled that far."""
    travelled = _travelled(record)

    def when(distance_mm: float | None, default: float) -> float:
        if distance_mm is None:
            return default
        for i in range(len(travelled)):
            if travelled[i] >= distance_mm:
                if i == 0:
                    return record.path[0][0]
                t0, t1 = record.path[i - 1][0], record.path[i][0]
                d0, d1 = travelled[i - 1], travelled[i]
                return t0 + (t1 - t0) * (distance_mm - d0) / (d1 - d0)
        return math.inf

    return when(from_mm, 0.0), when(to_mm, math.inf)


def _inside(record: RunRecord, names: tuple[str, ...]) -> list[Span]:
    """The stretches the robot's centre spent inside any of the regions ``names``."""
    regions = [world_regions(record)[name] for name in names]
    spans: list[Span] = []
    entered: float | None = None
    for t, x, y in dense_path(record.path):
        inside = any(region.contains(x, y) for region in regions)
        if inside and entered is None:
            entered = t
        elif not inside and entered is not None:
            spans.append((entered, t))
            entered = None
    if entered is not None:
        spans.append((entered, math.inf))
    return spans
