"""``max_duration``: the mission ends within a time limit (simulated time)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from roboscript.grading.expectations.base import Rule, SpecContext
from roboscript.grading.expectations.words import by, seconds
from roboscript.grading.record import RunRecord, Verdict
from roboscript.inputs.fields import FieldReader
from roboscript.inputs.source import Mark, YamlMap

if TYPE_CHECKING:
    from typing_extensions import Self  # annotations only: Python 3.10 has no typing.Self

__all__ = ["MaxDuration"]


@dataclass(frozen=True)
class MaxDuration(Rule):
    """``max_duration: 30 s``: the mission ends at most ``limit_s`` after its start."""

    kind = "max_duration"

    limit_s: float

    @classmethod
    def parse(cls, reader: FieldReader, value: object, mark: Mark, ctx: SpecContext) -> Self:
        holder = YamlMap.at(mark, {"max_duration": value})
        return cls(reader.positive(holder, "max_duration", "time", "s"))

    def judge(self, record: RunRecord) -> Verdict:
        limit_s = self.limit_s
        margin = limit_s - record.duration_s
        passed = margin >= 0
        return Verdict(
            "max_duration",
            passed,
            by(margin, seconds(margin)),
            None if passed else limit_s,
            f"the mission took {record.duration_s:.1f} s (allowed {limit_s:g} s)",
            margin,
            "s",
            margin / limit_s,
        )
