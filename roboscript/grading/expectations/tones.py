"""``tones``: how many tones the robot plays after the start, and which frequencies."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from roboscript.grading.expectations.base import Rule, SpecContext
from roboscript.grading.expectations.words import plural
from roboscript.grading.record import RunRecord, Verdict
from roboscript.inputs.fields import FieldReader
from roboscript.inputs.source import Mark, YamlMap

if TYPE_CHECKING:
    from typing_extensions import Self  # annotations only: Python 3.10 has no typing.Self

__all__ = ["DEFAULT_TONE_TOLERANCE_HZ", "Tones"]

DEFAULT_TONE_TOLERANCE_HZ = 5.0


@dataclass(frozen=True)
class Tones(Rule):
    """``tones``: how many (``count``, or ``min_count``/``max_count``), and which frequencies
    (``frequencies_hz`` in order, or one ``frequency_hz`` for every tone), each within
    ``tolerance_hz``."""

    kind = "tones"

    count: int | None = None
    min_count: int | None = None
    max_count: int | None = None
    frequencies_hz: tuple[float, ...] | None = None
    frequency_hz: float | None = None
    tolerance_hz: float = DEFAULT_TONE_TOLERANCE_HZ

    @classmethod
    def parse(cls, reader: FieldReader, value: object, mark: Mark, ctx: SpecContext) -> Self:
        data = reader.mapping(value, "tones", mark)
        keys = ("count", "min_count", "max_count", "frequencies", "frequency", "tolerance")
        reader.allowed(data, keys, "tones")
        if not data:
            raise reader.fail("tones needs at least one of: count, min_count, max_count, ...", mark)
        if "count" in data and ("min_count" in data or "max_count" in data):
            raise reader.fail(
                "give either count or min_count/max_count, not both", data.key_mark("count")
            )
        if "frequencies" in data and "frequency" in data:
            raise reader.fail(
                "give either frequencies (a list, in order) or frequency (every tone)",
                data.key_mark("frequency"),
            )
        counts = {
            k: reader.integer(data, k) for k in ("count", "min_count", "max_count") if k in data
        }
        if counts.get("min_count", 0) > counts.get("max_count", math.inf):
            raise reader.fail("min_count is more than max_count", data.key_mark("min_count"))
        frequencies = None
        if "frequencies" in data:
            items = reader.items(data["frequencies"], "frequencies", data.value_mark("frequencies"))
            if not items:
                raise reader.fail("frequencies lists at least one", data.value_mark("frequencies"))
            frequencies = tuple(_frequency(reader, v, m) for v, m in items)
            if "count" in counts and counts["count"] != len(frequencies):
                raise reader.fail(
                    f"count is {counts['count']} but frequencies lists {len(frequencies)}",
                    data.key_mark("count"),
                )
        return cls(
            count=counts.get("count"),
            min_count=counts.get("min_count"),
            max_count=counts.get("max_count"),
            frequencies_hz=frequencies,
            frequency_hz=(
                reader.positive(data, "frequency", "frequency", "Hz")
                if "frequency" in data
                else None
            ),
            tolerance_hz=(
                reader.positive(data, "tolerance", "frequency", "Hz")
                if "tolerance" in data
                else DEFAULT_TONE_TOLERANCE_HZ
            ),
        )

    def counts(self) -> tuple[int | None, int | None]:
        """The fewest and the most tones a run may play (``None``: no bound that way); a list
        of ``frequencies`` alone asks for exactly that many."""
        low = self.count if self.count is not None else self.min_count
        high = self.count if self.count is not None else self.max_count
        if self.frequencies_hz is not None and low is None and high is None:
            low = high = len(self.frequencies_hz)
        return low, high

    def wanted_hz(self, index: int) -> float | None:
        """The frequency wanted of the tone at ``index`` (0 for the first), in Hz, or ``None``
        when any frequency will do (past the end of ``frequencies``, or none given)."""
        if self.frequencies_hz is not None:
            return self.frequencies_hz[index] if index < len(self.frequencies_hz) else None
        return self.frequency_hz

    def judge(self, record: RunRecord) -> Verdict:
        played = record.tones
        n = len(played)
        heard = ", ".join(f"{t.frequency_hz:g} Hz" for t in played[:8]) + (" ..." if n > 8 else "")
        detail = f"{plural(n, 'tone')} played" + (f" ({heard})" if played else "")
        low, high = self.counts()
        # Problems, each with the moment it happened (None: only knowable at the end).
        problems: list[tuple[float | None, str, float]] = []
        if high is not None and n > high:
            problems.append((played[high].t_s, f"{plural(n - high, 'tone')} too many", n - high))
        if low is not None and n < low:
            problems.append((None, f"{plural(low - n, 'tone')} too few", low - n))
        for i, tone in enumerate(played):
            wanted = self.wanted_hz(i)
            if wanted is not None and abs(tone.frequency_hz - wanted) > self.tolerance_hz:
                problems.append(
                    (
                        tone.t_s,
                        f"tone {i + 1} was {tone.frequency_hz:g} Hz, expected {wanted:g} Hz",
                        abs(tone.frequency_hz - wanted),
                    )
                )
                break
        if not problems:
            return Verdict("tones", True, "", None, detail)
        problems.sort(key=lambda p: math.inf if p[0] is None else p[0])
        when, what, amount = problems[0]
        unit = "Hz" if "expected" in what else "tones"
        margin = (
            f"failed by {amount:g} Hz"
            if unit == "Hz"
            else f"failed by {plural(int(amount), 'tone')}"
        )
        return Verdict("tones", False, margin, when, f"{what}: {detail}", -amount, unit)


def _frequency(reader: FieldReader, value: object, mark: Mark) -> float:
    holder = YamlMap.at(mark, {"frequency": value})
    return reader.positive(holder, "frequency", "frequency", "Hz")
