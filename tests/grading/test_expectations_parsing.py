"""tones, wall_distance, final_pose_within and max_duration as a teacher writes them: units,
defaults, and each mistake named at its line and column in one sentence."""

from __future__ import annotations

from pathlib import Path

import pytest

from roboscript.errors import SpecError
from roboscript.grading.expectations import (
    FinalPose,
    MaxDuration,
    Selection,
    Tones,
    WallDistance,
)
from roboscript.grading.spec import load_test_spec


def _params(tmp_path: Path, expect: str) -> object:
    path = tmp_path / "spec.yaml"
    path.write_text(f"test: t\nworld: corridor\nexpect:\n  - {expect}\n", encoding="utf-8")
    return load_test_spec(path).expectations[0].rule


def _mistake(tmp_path: Path, expect: str) -> str:
    path = tmp_path / "spec.yaml"
    path.write_text(f"test: t\nworld: corridor\nexpect:\n  - {expect}\n", encoding="utf-8")
    with pytest.raises(SpecError) as caught:
        load_test_spec(path)
    text = caught.value.format()
    assert text.startswith(f"{path}:")
    return text.removeprefix(f"{path}:")


@pytest.mark.parametrize(
    ("expect", "tones"),
    [
        ("tones: {count: 3}", Tones(count=3)),
        ("tones: {min_count: 1, max_count: 4}", Tones(min_count=1, max_count=4)),
        (
            "tones: {frequencies: [440 Hz, 0.66 kHz, 880]}",
            Tones(frequencies_hz=(440.0, 660.0, 880.0)),
        ),
        (
            "tones: {count: 2, frequencies: [440, 660]}",
            Tones(count=2, frequencies_hz=(440.0, 660.0)),
        ),
        (
            "tones: {frequency: 523 Hz, tolerance: 10 Hz}",
            Tones(frequency_hz=523.0, tolerance_hz=10.0),
        ),
    ],
)
def test_tones_read_with_units(tmp_path: Path, expect: str, tones: Tones) -> None:
    assert _params(tmp_path, expect) == tones


def test_the_tone_tolerance_defaults_to_5_hz(tmp_path: Path) -> None:
    tones = _params(tmp_path, "tones: {frequency: 440 Hz}")
    assert isinstance(tones, Tones)
    assert tones.tolerance_hz == 5.0
    assert (tones.count, tones.min_count, tones.max_count, tones.frequencies_hz) == (
        None,
        None,
        None,
        None,
    )


@pytest.mark.parametrize(
    ("expect", "error"),
    [
        ("tones: {}", "4:12: error: tones needs at least one of: count, min_count, max_count, ..."),
        (
            "tones: {count: 2, max_count: 3}",
            "4:13: error: give either count or min_count/max_count, not both",
        ),
        (
            "tones: {count: 2, min_count: 1}",
            "4:13: error: give either count or min_count/max_count, not both",
        ),
        (
            "tones: {frequencies: [440], frequency: 440}",
            "4:33: error: give either frequencies (a list, in order) or frequency (every tone)",
        ),
        ("tones: {min_count: 3, max_count: 2}", "4:13: error: min_count is more than max_count"),
        ("tones: {frequencies: []}", "4:26: error: frequencies lists at least one"),
        (
            "tones: {count: 3, frequencies: [440, 660]}",
            "4:13: error: count is 3 but frequencies lists 2",
        ),
        (
            "tones: {frequencies: [440, 5 cm]}",
            "4:32: error: 'cm' is a unit of distance, but this is a frequency (use hz, khz)",
        ),
        ("tones: {frequency: -440 Hz}", "4:24: error: 'frequency' must be more than 0"),
        ("tones: {count: 1, tolerance: 0 Hz}", "4:34: error: 'tolerance' must be more than 0"),
        ("tones: {cuont: 1}", "4:13: error: unknown key 'cuont' in tones (did you mean 'count'?)"),
        ("tones: 3", "4:12: error: tones must be a mapping"),
        ("tones: {frequencies: 440}", "4:26: error: frequencies must be a list"),
    ],
)
def test_mistakes_in_tones_are_located(tmp_path: Path, expect: str, error: str) -> None:
    assert _mistake(tmp_path, expect).startswith(error)


def test_a_silent_robot_can_be_asked_for(tmp_path: Path) -> None:
    assert _params(tmp_path, "tones: {max_count: 0}") == Tones(max_count=0)


def test_min_count_may_equal_max_count(tmp_path: Path) -> None:
    assert _params(tmp_path, "tones: {min_count: 2, max_count: 2}") == Tones(
        min_count=2, max_count=2
    )


def test_wall_distance_reads_with_units_and_defaults(tmp_path: Path) -> None:
    rule = _params(tmp_path, "wall_distance: {state: follow, min: 15 cm, max: 0.25 m}")
    assert rule == WallDistance(
        side="right", min_mm=150.0, max_mm=250.0, selection=Selection(state="follow", settle_s=1.0)
    )
    left = _params(tmp_path, "wall_distance: {state: f, max: 30 cm, side: left, settle: 2 s}")
    assert left == WallDistance(
        side="left", min_mm=None, max_mm=300.0, selection=Selection(state="f", settle_s=2.0)
    )
    at_least = _params(tmp_path, "wall_distance: {state: f, min: 0 cm, settle: 0 s}")
    assert at_least == WallDistance(
        side="right", min_mm=0.0, max_mm=None, selection=Selection(state="f", settle_s=0.0)
    )


@pytest.mark.parametrize(
    ("expect", "error"),
    [
        ("wall_distance: {state: f}", "4:20: error: wall_distance needs min, max or both"),
        (
            "wall_distance: {state: f, min: 20 cm, max: 20 cm}",
            "4:36: error: min must be less than max",
        ),
        ("wall_distance: {state: f, max: 0 cm}", "4:36: error: 'max' must be more than 0"),
        (
            "wall_distance: {state: f, min: 1 cm, settle: -1 s}",
            "4:50: error: settle cannot be negative",
        ),
        (
            "wall_distance: {state: f, min: 1 cm, side: up}",
            "4:48: error: 'side' must be one of: left, right (got 'up')",
        ),
        (
            "wall_distance: {min: 1 cm, during: whole ru}",
            (
                "4:40: error: during is 'whole run' or a time window such as during: {from: 5 s,"
                " to: 20 s} (got 'whole ru') (did you mean 'whole run'?)"
            ),
        ),
        ("wall_distance: {min: 1 cm, durng: whole run}", "4:32: error: unknown key 'durng'"),
        ("wall_distance: {min: 1 cm, during: {from: 5 s, too: 9 s}}", "4:52: error: unknown"),
        (
            "wall_distance: {min: 1 cm, along: {from: 2 m, to: 1 m}}",
            "4:55: error: 'from' must come before 'to'",
        ),
        (
            "wall_distance: {min: 1 cm, along: {}}",
            "4:39: error: along needs from, to or both, such as along: {from: 50 cm, to: 2.5 m}",
        ),
        (
            "wall_distance: {min: 1 cm, in_region: far-edn}",
            (
                "4:43: error: the world 'corridor' has no region 'far-edn' (its regions: far-end,"
                " start-zone) (did you mean 'far-end'?)"
            ),
        ),
    ],
)
def test_mistakes_in_wall_distance_are_located(tmp_path: Path, expect: str, error: str) -> None:
    assert _mistake(tmp_path, expect).startswith(error)


def test_final_pose_reads_with_units_and_defaults(tmp_path: Path) -> None:
    pose = _params(tmp_path, "final_pose_within: {x: 1 m, y: -20 cm, radius: 5 cm}")
    assert pose == FinalPose(1000.0, -200.0, 50.0, None, 15.0, "world")
    facing = _params(
        tmp_path,
        "final_pose_within: {x: 0, y: 0, radius: 5 cm, heading: 0.25 rev,"
        " heading_tolerance: 5 deg, relative_to: start}",
    )
    assert facing == FinalPose(0.0, 0.0, 50.0, 90.0, 5.0, "start")


@pytest.mark.parametrize(
    ("expect", "error"),
    [
        (
            "final_pose_within: {x: 0, y: 0, radius: 5 cm, heading_tolerance: 5 deg}",
            "4:51: error: heading_tolerance needs a heading to compare with",
        ),
        (
            "final_pose_within: {x: 0, y: 0, radius: 0 cm}",
            "4:45: error: 'radius' must be more than 0",
        ),
        (
            "final_pose_within: {x: 0, y: 0, radius: 1, relative_to: here}",
            "4:61: error: 'relative_to' must be one of: world, start (got 'here')",
        ),
        ("final_pose_within: {x: 0, radius: 1}", "4:24: error:"),
    ],
)
def test_mistakes_in_final_pose_are_located(tmp_path: Path, expect: str, error: str) -> None:
    assert _mistake(tmp_path, expect).startswith(error)


def test_max_duration_reads_a_time(tmp_path: Path) -> None:
    assert _params(tmp_path, "max_duration: 1.5 min") == MaxDuration(90.0)
    assert _mistake(tmp_path, "max_duration: 0 s").startswith(
        "4:19: error: 'max_duration' must be more than 0"
    )
