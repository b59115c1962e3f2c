"""``max_duration``: the mission ends within its time limit."""

from __future__ import annotations

from pathlib import Path

import pytest
from grading.expectations.runs import _judge, _mistake, _north, _params, _record

from roboscript.grading.expectations import MaxDuration
from roboscript.grading.record import Verdict


def test_max_duration_margin_in_seconds() -> None:
    assert _judge(MaxDuration(30.0), _record(_north(20.0))).margin == "passed by 10.0 s"
    late = _judge(MaxDuration(30.0), _record(_north(30.4)))
    assert not late.passed
    assert late.margin == "failed by 0.40 s"
    assert late.first_violation_s == 30.0


def test_max_duration_reads_a_time(tmp_path: Path) -> None:
    assert _params(tmp_path, "max_duration: 1.5 min") == MaxDuration(90.0)
    assert _mistake(tmp_path, "max_duration: 0 s").startswith(
        "4:19: error: 'max_duration' must be more than 0"
    )


def test_max_duration_passes_up_to_and_including_the_limit() -> None:
    on_time = _judge(MaxDuration(30.0), _record(_north(30.0)))
    assert on_time.passed is True
    assert on_time.first_violation_s is None
    early = _judge(MaxDuration(30.0), _record(_north(29.5)))
    assert early == Verdict(
        "max_duration",
        True,
        "passed by 0.50 s",
        None,
        "the mission took 29.5 s (allowed 30 s)",
        0.5,
        "s",
        0.5 / 30.0,
    )


@pytest.mark.parametrize(
    ("limit_s", "margin"), [(6.0, "passed by 1.0 s"), (5.5, "passed by 0.50 s")]
)
def test_a_margin_under_a_second_has_two_decimals(limit_s: float, margin: str) -> None:
    assert _judge(MaxDuration(limit_s), _record(_north(5.0))).margin == margin
