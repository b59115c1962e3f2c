"""How the mission ended: ``outcome`` and ``final_state`` (the mission's own account of it)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from roboscript.errors import did_you_mean
from roboscript.grading.expectations.base import Rule, SpecContext
from roboscript.grading.record import RunRecord, Verdict
from roboscript.inputs.fields import FieldReader
from roboscript.inputs.source import Mark, YamlMap

if TYPE_CHECKING:
    from typing_extensions import Self  # annotations only: Python 3.10 has no typing.Self

__all__ = ["FinalState", "Outcome"]


@dataclass(frozen=True)
class Outcome(Rule):
    """``outcome: success``: how the mission must end (``success`` or ``failure``)."""

    kind = "outcome"

    wanted: str

    @classmethod
    def parse(cls, reader: FieldReader, value: object, mark: Mark, ctx: SpecContext) -> Self:
        if value not in ("success", "failure"):
            hint = did_you_mean(str(value), ("success", "failure"))
            raise reader.fail(f"outcome must be success or failure (got {value!r})", mark, hint)
        return cls(str(value))

    def judge(self, record: RunRecord) -> Verdict:
        passed = record.outcome == self.wanted
        detail = f"the mission ended in {record.outcome}"
        if record.reason:
            detail += f": {record.reason}"  # the reason names the state
        elif record.final_state:
            detail += f" in state '{record.final_state}'"
        return Verdict(
            "outcome",
            passed,
            first_violation_s=None if passed else record.duration_s,
            detail=detail,
        )


@dataclass(frozen=True)
class FinalState(Rule):
    """``final_state: home`` (or a list): the state, or one of the states, to end in."""

    kind = "final_state"

    names: tuple[str, ...]

    @classmethod
    def parse(cls, reader: FieldReader, value: object, mark: Mark, ctx: SpecContext) -> Self:
        holder = YamlMap.at(mark, {"final_state": value})
        return cls(tuple(name for name, _ in reader.names(holder, "final_state")))

    def judge(self, record: RunRecord) -> Verdict:
        passed = record.final_state in self.names
        expected = " or ".join(f"'{name}'" for name in self.names)
        detail = f"ended in '{record.final_state}' (expected {expected})"
        return Verdict(
            "final_state",
            passed,
            first_violation_s=None if passed else record.duration_s,
            detail=detail,
        )
