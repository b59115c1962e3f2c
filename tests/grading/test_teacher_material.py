"""The teacher specs in missions/teacher/: the good solution passes every run, the bad one fails
every run, for the mistake it was written to show."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from helpers import MISSIONS, run_cli

from roboscript.grading.run import grade_run
from roboscript.grading.spec import load_test_spec

TEACHER = MISSIONS / "teacher"

# test folder -> the expectation that catches the bad solution's mistake on its first run
MISTAKES = {
    "square": "path_visits",  # stops after three sides (visits.side >= 3): never back home
    "corridor": "wall_distance",  # 'distance: 20' is 20 mm, not 20 cm: it scrapes the wall
    "line-track": "check: stays_on_line",  # drives a rectangle "by heart" instead of following
}


def test_every_teacher_test_has_a_good_and_a_bad_solution() -> None:
    folders = sorted(p.parent.name for p in TEACHER.glob("*/test.yaml"))
    assert folders == sorted(MISTAKES)
    for name in folders:
        assert (TEACHER / name / "good.yaml").is_file()
        assert (TEACHER / name / "bad.yaml").is_file()


def _grade(folder: str, solution: str) -> dict[str, object]:
    result = run_cli(
        "grade",
        str(TEACHER / folder / "test.yaml"),
        "--mission",
        str(TEACHER / folder / f"{solution}.yaml"),
        "--json",
    )
    assert result.returncode in (0, 1), result.stderr
    report: dict[str, object] = json.loads(result.stdout)
    return report


@pytest.mark.parametrize("folder", sorted(MISTAKES))
def test_the_good_solution_passes_every_run(folder: str) -> None:
    report = _grade(folder, "good")
    runs = report["runs"]
    assert isinstance(runs, list) and len(runs) >= 2
    assert [r["status"] for r in runs] == ["passed"] * len(runs), [r["message"] for r in runs]


@pytest.mark.parametrize("folder", sorted(MISTAKES))
def test_the_bad_solution_fails_every_run_for_its_mistake(folder: str) -> None:
    report = _grade(folder, "bad")
    runs = report["runs"]
    assert isinstance(runs, list)
    assert all(r["status"] == "failed" for r in runs)
    failed = [v["name"] for v in runs[0]["verdicts"] if not v["passed"]]
    assert MISTAKES[folder] in failed


def test_teacher_specs_are_not_examples_for_the_mission_tests() -> None:
    # tests/test_missions.py runs missions/*.yaml; the teacher folder must stay out of it.
    top_level = {p.name for p in MISSIONS.glob("*.yaml")}
    assert not any(Path(name).stem in {"test", "good", "bad"} for name in top_level)


# Four wrong squares the first square spec passed on every run (12 of 12): it checked only that
# the robot ended where it started, after 4 beeps. Each must now fail every run, and for this.
_SIDE = """\
mission: square
initial: side
states:
  side:
    do: {{drive: {{distance: {side}, speed: 15 cm/s}}}}
    on: {{done: corner, failed: stuck}}
  corner:
    do: {{rotate: {{angle: {angle}}}}}
    on: {{done: beep, failed: stuck}}
  beep:
    do: {{play_tone: {{frequency: 880 Hz, duration: 200 ms}}}}
    on:
      done:
        - {{if: "visits.side >= 4", goto: finished}}
        - {{goto: side}}
  stuck:
    final: failure
  finished:
    final: success
"""

WRONG_SQUARES = {
    "only-beeps": (
        """\
mission: square
initial: beep
states:
  beep:
    do: {play_tone: {frequency: 880 Hz, duration: 200 ms}}
    on:
      done:
        - {if: "visits.beep >= 4", goto: finished}
        - {goto: pause}
  pause:
    do: {wait: {duration: 300 ms}}
    on: {done: beep}
  finished:
    final: success
""",
        {"path_visits", "turns"},
    ),
    "44-cm": (_SIDE.format(side="44 cm", angle="90 deg"), {"path_visits"}),
    "left-turning": (_SIDE.format(side="50 cm", angle="-90 deg"), {"path_visits", "turns"}),
    "spins-on-the-spot": (
        """\
mission: square
initial: corner
states:
  corner:
    do: {rotate: {angle: 90 deg}}
    on: {done: beep, failed: stuck}
  beep:
    do: {play_tone: {frequency: 880 Hz, duration: 200 ms}}
    on:
      done:
        - {if: "visits.corner >= 4", goto: finished}
        - {goto: corner}
  stuck:
    final: failure
  finished:
    final: success
""",
        # Four rotations on the spot with no travel between them are one 360° turn.
        {"path_visits", "turns"},
    ),
}


@pytest.mark.parametrize("name", sorted(WRONG_SQUARES))
def test_a_wrong_square_fails_every_run(tmp_path: Path, name: str) -> None:
    text, catches = WRONG_SQUARES[name]
    mission = tmp_path / f"{name}.yaml"
    mission.write_text(text, encoding="utf-8")
    spec = load_test_spec(TEACHER / "square" / "test.yaml")
    assert len(spec.variants) == 3
    for variant in spec.variants:
        result = grade_run(spec, str(mission), variant)
        failed = {v.name for v in result.verdicts if not v.passed}
        assert result.status == "failed", (variant.label, result.status, result.message)
        assert failed == catches, (variant.label, result.message)
        # What the old spec checked still holds: the mistake is in the shape, not the ending.
        held = {v.name for v in result.verdicts if v.passed}
        assert {"outcome", "final_pose_within", "tones", "no_collisions"} <= held


def test_the_good_square_passes_the_shape_checks_with_room_to_spare() -> None:
    spec = load_test_spec(TEACHER / "square" / "test.yaml")
    for variant in spec.variants:
        result = grade_run(spec, str(TEACHER / "square" / "good.yaml"), variant)
        assert result.status == "passed", result.message
        margins = {v.name: v.relative_margin for v in result.verdicts}
        assert (margins["path_visits"] or 0.0) > 0.5  # within 2 cm of every corner (of 4)
        assert (margins["turns"] or 0.0) > 0.5


# Lazy and cheating missions, graded through `roboscript grade` against every shipped test: each
# earns what its robot did, which is nothing (what every test requires fails on every run).
LAZY = {
    "instant-success": """\
mission: lazy
initial: done
states:
  done:
    final: success
""",
    "names-the-states": """\
mission: names
initial: follow
states:
  follow:
    do: {wait: {duration: 2 s}}
    on: {done: side}
  side:
    do: {wait: {duration: 1 s}}
    on: {done: corner}
  corner:
    do: {play_tone: {frequency: 880 Hz, duration: 200 ms}}
    on:
      done:
        - {if: "visits.corner >= 4", goto: lap_done}
        - {goto: side}
  lap_done:
    final: success
""",
    "spins-in-place": """\
mission: spin
initial: corner
states:
  corner:
    do: {rotate: {angle: 90 deg}}
    on: {done: beep}
  beep:
    do: {play_tone: {frequency: 880 Hz, duration: 200 ms}}
    on:
      done:
        - {if: "visits.corner >= 4", goto: finished}
        - {goto: corner}
  finished:
    final: success
""",
    # Straight ahead for 3 m, whatever the course: in the corridor it stays in the band only
    # from a start that happens to face along the wall at the right distance.
    "drives-straight": """\
mission: straight
initial: go
states:
  go:
    do: {drive: {distance: 3 m, speed: 20 cm/s}}
    timeout: 25 s
    on: {done: finished, failed: finished, timeout: finished}
  finished:
    final: success
""",
}


@pytest.fixture(scope="module")
def lazy_class(tmp_path_factory: pytest.TempPathFactory) -> dict[str, object]:
    folder = tmp_path_factory.mktemp("lazy")
    for student, text in LAZY.items():
        (folder / f"{student}.yaml").write_text(text, encoding="utf-8")
    specs = sorted(str(p) for p in TEACHER.glob("*/test.yaml"))
    result = run_cli("grade", *specs, "--mission", str(folder), "--json", "--jobs", "2")
    assert result.returncode == 1, result.stderr
    assert "Traceback" not in result.stderr, result.stderr
    report: dict[str, object] = json.loads(result.stdout)
    return report


@pytest.mark.parametrize("student", sorted(LAZY))
def test_a_lazy_mission_scores_0_on_every_shipped_test(
    lazy_class: dict[str, object], student: str
) -> None:
    runs = lazy_class["runs"]
    assert isinstance(runs, list)
    mine = [r for r in runs if r["student"] == student]
    assert {r["test"] for r in mine} == {"corridor-wall-follow", "line-track-lap", "square-50cm"}
    for run in mine:
        assert run["score"] == 0.0, (run["test"], run["label"], run["message"])
        assert "(required: without it the run scores 0)" in run["message"]
