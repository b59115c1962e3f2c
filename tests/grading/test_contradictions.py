"""Expectations no run can meet, told when a spec is read (roboscript.grading.expectations
.contradictions): what a teacher's spec of any size costs to check."""

from __future__ import annotations

import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from types import FrameType
from typing import Any

import pytest

from roboscript.errors import SpecError
from roboscript.grading.spec import load_test_spec

CALLS_A_SPEC_MAY_TAKE = 200_000
"""Far more Python calls than reading any spec of a few lines takes, and far fewer than a
check that walks every tone of a count of a billion."""


class _TooManyCallsError(Exception):
    pass


@contextmanager
def _calls_bounded(most: int) -> Iterator[None]:
    """Raise _TooManyCallsError once the code inside has made ``most`` Python calls: a check that
    would run for hours fails at once instead, whatever the machine's speed."""
    made = 0

    def count(frame: FrameType, event: str, arg: Any) -> None:
        nonlocal made
        if event == "call":
            made += 1
            if made > most:
                raise _TooManyCallsError(f"more than {most} calls")

    sys.settrace(count)
    try:
        yield
    finally:
        sys.settrace(None)


def _write(tmp_path: Path, expect: str) -> Path:
    path = tmp_path / "spec.yaml"
    path.write_text(f"test: t\nexpect:\n{expect}", encoding="utf-8")
    return path


def test_tones_asking_for_a_huge_count_are_checked_without_walking_every_tone(
    tmp_path: Path,
) -> None:
    path = _write(
        tmp_path,
        "  - tones: {min_count: 1000000000000, frequency: 440 Hz}\n"
        "  - tones: {min_count: 1000000000000, frequency: 440 Hz}\n",
    )
    with _calls_bounded(CALLS_A_SPEC_MAY_TAKE):
        spec = load_test_spec(path)
    assert len(spec.expectations) == 2


@pytest.mark.parametrize(
    ("expect", "clash"),
    [
        pytest.param(
            "  - tones: {min_count: 1000000000000, frequency: 440 Hz}\n"
            "  - tones: {min_count: 1000000000000, frequency: 880 Hz}\n",
            "tone 1 cannot be both 440 Hz (±5) and 880 Hz (±5)",
            id="one-frequency-each",
        ),
        pytest.param(
            "  - tones: {min_count: 1000000000000, frequency: 440 Hz}\n"
            "  - tones: {frequencies: [440 Hz, 440 Hz, 880 Hz], min_count: 1000000000000}\n",
            "tone 3 cannot be both 440 Hz (±5) and 880 Hz (±5)",
            id="past-the-list's-agreement",
        ),
    ],
)
def test_tones_wanting_other_frequencies_of_a_huge_count_are_told_at_the_first_that_differs(
    tmp_path: Path, expect: str, clash: str
) -> None:
    path = _write(tmp_path, expect)
    with _calls_bounded(CALLS_A_SPEC_MAY_TAKE), pytest.raises(SpecError) as caught:
        load_test_spec(path)
    assert clash in caught.value.format()


def test_a_clash_is_said_to_be_a_runs_own_targets_only_when_they_are(tmp_path: Path) -> None:
    path = tmp_path / "spec.yaml"
    runs = (
        "runs:\n"
        "  - {seed: 1}\n"
        "  - {seed: 2, expect: {final_pose_within: {x: 0 mm, y: 50 cm, radius: 5 cm}}}\n"
    )
    expect = "  - final_pose_within: {x: 0 mm, y: 0 mm, radius: 5 cm}\n"
    path.write_text(
        f"test: t\n{runs}expect:\n{expect}  - outcome: success\n  - outcome: failure\n",
        encoding="utf-8",
    )
    with pytest.raises(SpecError) as caught:
        load_test_spec(path)
    assert caught.value.format().endswith(
        "this outcome contradicts the outcome on line 7: a mission ends in success or in"
        " failure, not both"
    ), caught.value.format()


def test_a_clash_with_a_runs_own_targets_names_that_run(tmp_path: Path) -> None:
    path = tmp_path / "spec.yaml"
    path.write_text(
        "test: t\nworld: corridor\nruns:\n"
        "  - {seed: 1}\n"
        "  - {seed: 2, expect: {final_pose_within: {x: 0 mm, y: 2700 mm, radius: 5 cm}}}\n"
        "expect:\n"
        "  - final_pose_within: {x: 0 mm, y: 1000 mm, radius: 5 cm}\n"
        "  - never_enter: far-end\n",
        encoding="utf-8",
    )
    with pytest.raises(SpecError) as caught:
        load_test_spec(path)
    assert "this never_enter contradicts the final_pose_within on line 7 (run 2's targets):" in (
        caught.value.format()
    ), caught.value.format()
