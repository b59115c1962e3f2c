"""The defaults the teachers' guide promises are the grader's defaults.

docs/teachers/grading.md states each expectation's default tolerance; a teacher who leaves it
out relies on that number, so the code may not drift from it (a tone 50 Hz off must not pass
a ``frequency: 880 Hz`` test that the guide says allows 5 Hz).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from helpers import ROOT

from roboscript.grading import expectations as ex
from roboscript.grading import spec as sp
from roboscript.grading.expectations import (
    Expectation,
    Tones,
    evaluate,
)
from roboscript.grading.record import RunRecord, Tone
from roboscript.grading.spec import load_test_spec
from roboscript.sim.world import World

GUIDE = (ROOT / "docs" / "teachers" / "grading.md").read_text(encoding="utf-8")
_TO_SI = {"Hz": 1.0, "°": 1.0, "s": 1.0, "cm": 10.0, "mm": 1.0}


def _documented(pattern: str) -> float:
    """The number (in Hz, degrees, seconds or mm) the guide gives where ``pattern`` matches."""
    found = re.findall(pattern, " ".join(GUIDE.split()))
    assert len(found) == 1, f"the guide says {pattern!r} {len(found)} times"
    number, unit = found[0]
    return float(number) * _TO_SI[unit]


@pytest.mark.parametrize(
    ("pattern", "value"),
    [
        (r"`tolerance` \(default (\d+) (Hz)\)", ex.DEFAULT_TONE_TOLERANCE_HZ),
        (r"`heading_tolerance` \(default (\d+)(°)\)", ex.DEFAULT_HEADING_TOLERANCE_DEG),
        (r"after `settle`, default (\d+) (s)", ex.DEFAULT_SETTLE_S),
        (
            r"within `tolerance` \(default (\d+) (cm)\) of each waypoint",
            ex.DEFAULT_WAYPOINT_TOLERANCE_MM,
        ),
        (r"- `tolerance`: default (\d+)(°)", ex.DEFAULT_TURN_TOLERANCE_DEG),
        (r"`distance` ± `tolerance` \(default (\d+) (cm)\)", ex.DEFAULT_WALL_AHEAD_TOLERANCE_MM),
        (r"max_time: \d+ s # simulated time per run \(default (\d+) (s)\)", sp.DEFAULT_MAX_TIME_S),
        (
            r"real time per run before it is stopped \(default (\d+) (s)\)",
            sp.DEFAULT_WALL_TIME_LIMIT_S,
        ),
    ],
    ids=[
        "tones",
        "final_pose_heading",
        "wall_distance_settle",
        "path_visits",
        "turns",
        "wall_ahead_at_end",
        "max_time",
        "wall_time_limit",
    ],
)
def test_the_guide_and_the_code_agree_on_defaults(pattern: str, value: float) -> None:
    assert _documented(pattern) == pytest.approx(value)


def _record(*frequencies_hz: float) -> RunRecord:
    return RunRecord.simulated(
        mission="m",
        robot="mirto",
        world_name="empty",
        seed=1,
        outcome="success",
        final_state="done",
        reason=None,
        duration_s=5.0,
        states=((0.0, "go"),),
        path=((0.0, 0.0, 0.0, 0.0), (5.0, 0.0, 0.0, 0.0)),
        tones=tuple(Tone(1.0 + i, f, 0.2) for i, f in enumerate(frequencies_hz)),
        collisions=(),
        final_pose=(0.0, 0.0, 0.0),
        world=World("empty"),
    )


def test_a_tones_test_without_a_tolerance_allows_5_hz(tmp_path: Path) -> None:
    path = tmp_path / "beep.yaml"
    path.write_text("test: beep\nexpect:\n  - tones: {frequency: 880 Hz}\n", encoding="utf-8")
    (tones,) = load_test_spec(path).expectations
    assert tones.rule == Tones(frequency_hz=880.0, tolerance_hz=5.0)
    assert evaluate(tones, _record(884.9, 875.1)).passed
    off = evaluate(tones, _record(880.0, 885.2))
    assert not off.passed
    assert off.detail.startswith("tone 2 was 885.2 Hz, expected 880 Hz")


def test_a_tones_expectation_made_in_python_allows_5_hz() -> None:
    expectation = Expectation(Tones(frequencies_hz=(440.0, 880.0)))
    assert evaluate(expectation, _record(444.0, 876.0)).passed
    assert not evaluate(expectation, _record(446.0, 880.0)).passed
