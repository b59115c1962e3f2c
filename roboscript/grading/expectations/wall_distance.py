"""``wall_distance``: the gap to keep to a wall on one side, over the stretches it selects."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from roboscript.grading.expectations.base import Rule, SpecContext
from roboscript.grading.expectations.selection import SELECTION_KEYS, Selection
from roboscript.grading.expectations.words import at, by, cm
from roboscript.grading.record import RunRecord, Verdict
from roboscript.grading.regions import nearest_wall_gap_mm
from roboscript.inputs.fields import FieldReader
from roboscript.inputs.source import Mark

if TYPE_CHECKING:
    from typing_extensions import Self  # annotations only: Python 3.10 has no typing.Self

__all__ = ["WallDistance"]


@dataclass(frozen=True)
class WallDistance(Rule):
    """``wall_distance``: the gap from the side sensor to the nearest wall on ``side``, at
    least ``min_mm`` and at most ``max_mm``, wherever ``selection`` judges (the whole run
    unless the spec says otherwise; see :class:`Selection`)."""

    kind = "wall_distance"

    side: str = "right"
    min_mm: float | None = None
    max_mm: float | None = None
    selection: Selection = field(default_factory=Selection)

    @classmethod
    def parse(cls, reader: FieldReader, value: object, mark: Mark, ctx: SpecContext) -> Self:
        data = reader.mapping(value, "wall_distance", mark)
        reader.allowed(data, ("min", "max", "side", *SELECTION_KEYS), "wall_distance")
        if "min" not in data and "max" not in data:
            raise reader.fail("wall_distance needs min, max or both", data.mark)
        low = reader.quantity(data, "min", "distance", "mm") if "min" in data else None
        high = reader.positive(data, "max", "distance", "mm") if "max" in data else None
        if low is not None and high is not None and low >= high:
            raise reader.fail("min must be less than max", data.value_mark("min"))
        for world in ctx.worlds:
            if not world.walls:  # with max, every run fails; with min alone, every run passes
                raise reader.fail(
                    f"the world '{world.name}' has no walls, so there is never a wall beside"
                    " the robot to keep a distance from",
                    mark,
                )
        return cls(
            side=reader.choice(data, "side", ("left", "right")) if "side" in data else "right",
            min_mm=low,
            max_mm=high,
            selection=Selection.parse(reader, data, ctx),
        )

    def judge(self, record: RunRecord) -> Verdict:
        where = self.selection
        spans = where.spans(record)
        walls = record.world.walls if record.world is not None else ()
        worst = (math.inf, 0.0, 0.0)  # (margin, time, gap)
        first: float | None = None
        samples = 0
        for t, x, y, heading in record.path:
            if not where.judged(t, spans):
                continue
            samples += 1
            gap = nearest_wall_gap_mm(walls, x, y, heading, self.side, record.side_sensor_offset_mm)
            margin = min(
                gap - self.min_mm if self.min_mm is not None else math.inf,
                self.max_mm - gap if self.max_mm is not None else math.inf,
            )
            if margin < worst[0]:
                worst = (margin, t, gap)
            if margin < 0 and first is None:
                first = t
        if samples == 0:
            return Verdict(
                "wall_distance",
                False,
                "",
                None,
                where.never(record)
                or f"the robot never stayed {where.text} longer than the {where.settle_s:g} s"
                " it is given to settle",
            )
        margin, when, gap = worst
        if math.isinf(margin) and margin > 0:
            return Verdict(
                "wall_distance",
                True,
                "",
                None,
                f"no {self.side} wall was ever closer than allowed",
            )
        seen = "no wall in sight" if math.isinf(gap) else f"{cm(gap)}"
        detail = (
            f"{where.text} the {self.side} gap must stay {self.band};"
            f" the worst was {seen} at {at(when)}"
        )
        if math.isinf(margin):
            return Verdict("wall_distance", False, "", first, detail)
        scale = self.band_scale
        return Verdict(
            "wall_distance",
            margin >= 0,
            by(margin, cm(margin)),
            first,
            detail,
            margin,
            "mm",
            margin / scale if scale > 0 else None,
        )

    @property
    def band(self) -> str:
        """The band in words: ``between 12.0 cm and 28.0 cm``, ``at least 5.0 cm``."""
        if self.min_mm is not None and self.max_mm is not None:
            return f"between {cm(self.min_mm)} and {cm(self.max_mm)}"
        if self.min_mm is not None:
            return f"at least {cm(self.min_mm)}"
        return f"at most {cm(self.max_mm or 0.0)}"

    @property
    def band_scale(self) -> float:
        """What a relative margin of 1 is: half the band, or its one edge."""
        if self.min_mm is not None and self.max_mm is not None:
            return (self.max_mm - self.min_mm) / 2.0
        return self.min_mm if self.min_mm is not None else self.max_mm or 0.0
