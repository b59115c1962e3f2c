"""A grade follows what the robot physically did, through the real ``roboscript grade``.

Each class below is graded once, in a child process, as a teacher runs it: a robot that follows
the wall only in the state it names ``follow``, a mission that does nothing and succeeds, one
that beeps before its start, and corners made of two 45° rotations. The hang limit is generous
so that a busy machine cannot turn a verdict into ``hung``: these tests judge the verdicts,
not the grader's patience.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path
from typing import Any

import pytest
from helpers import HANG_BOUND_S, MISSIONS, run_cli

TEACHER = MISSIONS / "teacher"

WALL_ONLY_IN_FOLLOW = """\
mission: corridor-follow
world: corridor
initial: follow
states:
  follow:
    do: {follow_wall: {side: right, distance: 20 cm, speed: 15 cm/s, duration: 7 s}}
    on: {done: veer, failed: lost}
  veer:
    do: {rotate: {angle: -25 deg}}
    on: {done: cross, failed: lost}
  cross:
    do: {drive: {distance: 40 cm, speed: 15 cm/s}}
    on: {done: straighten, failed: lost}
  straighten:
    do: {rotate: {angle: 25 deg}}
    on: {done: dash, failed: lost}
  dash:
    do: {drive: {distance: 130 cm, speed: 15 cm/s}}
    on: {done: arrived, failed: lost}
  arrived:
    do: {play_tone: {frequency: 880 Hz, duration: 300 ms}}
    final: success
  lost:
    final: failure
"""

DOES_NOTHING = """\
mission: nothing
initial: done
states:
  done:
    final: success
"""

BEEPS_BEFORE_ITS_START = """\
import sys

from roboscript import Mission, Wait, state
from roboscript.transport.lockstep import Kind, WorldChannel

# Four tones sent straight down the wire while the mission loads, before it starts.
channel = WorldChannel.for_fd(int(sys.argv[1]))
channel.send(Kind.OPEN)
for _ in range(4):
    channel.send(Kind.WRITE, b"T,P,880,100\\n")
channel.request(Kind.SYNC)


class Early(Mission):
    go = state(Wait(duration_s=0.5), initial=True, on_done="end")
    end = state(final="success")
"""

TONES_SPEC = """\
test: four-beeps
world: empty
robot: mirto
runs:
  - {seed: 1}
max_time: 10 s
expect:
  - outcome: success
  - tones: {count: 4}
"""

HALF_CORNERS = """\
mission: square-in-halves
initial: side
states:
  side:
    do: {drive: {distance: 50 cm, speed: 15 cm/s}}
    on: {done: half}
  half:
    do: {rotate: {angle: 45 deg}}
    on: {done: other_half}
  other_half:
    do: {rotate: {angle: 45 deg}}
    on: {done: beep}
  beep:
    do: {play_tone: {frequency: 880 Hz, duration: 200 ms}}
    on:
      done:
        - {if: "visits.side >= 4", goto: finished}
        - {goto: side}
  finished:
    final: success
"""

CORNERS_SPEC = """\
test: four-corners
world: empty
robot: mirto
runs:
  - {seed: 1}
  - {seed: 2}
  - {seed: 3}
max_time: 60 s
expect:
  - turns: {count: 4}
"""


def _grade(folder: Path, *specs: Path) -> dict[str, Any]:
    """``roboscript grade SPECS --mission FOLDER --json``, its report."""
    result = run_cli(
        "grade", *map(str, specs), "--mission", str(folder), "--json", "--jobs", "2",
        "--hang-after", "60",
        timeout=HANG_BOUND_S,
    )  # fmt: skip
    assert "Traceback" not in result.stderr, result.stderr
    report: dict[str, Any] = json.loads(result.stdout)
    return report


def _class(root: Path, name: str, **missions: str) -> Path:
    folder = root / name
    folder.mkdir()
    for student, text in missions.items():
        suffix = ".py" if text.startswith("import") else ".yaml"
        (folder / f"{student}{suffix}").write_text(text, encoding="utf-8")
    return folder


def _runs(report: dict[str, Any], student: str, test: str) -> list[dict[str, Any]]:
    runs = [r for r in report["runs"] if r["student"] == student and r["test"] == test]
    assert runs, f"no runs of {student} on {test}"
    return runs


def _verdict(run: dict[str, Any], name: str) -> dict[str, Any]:
    found: dict[str, Any] = next(v for v in run["verdicts"] if v["name"] == name)
    return found


@pytest.fixture(scope="module")
def corridor(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    root = tmp_path_factory.mktemp("corridor")
    folder = _class(root, "class", cheat=WALL_ONLY_IN_FOLLOW)
    shutil.copy(TEACHER / "corridor" / "good.yaml", folder / "honest.yaml")
    return _grade(folder, TEACHER / "corridor" / "test.yaml")


def test_following_the_wall_only_in_the_state_named_follow_fails_the_corridor(
    corridor: dict[str, Any],
) -> None:
    for run in _runs(corridor, "cheat", "corridor-wall-follow"):
        assert run["status"] == "failed"
        assert run["score"] == 0.0  # the band is required
        band = _verdict(run, "wall_distance")
        assert not band["passed"]
        assert band["detail"].startswith("over the whole run the right gap must stay between")
        # It left the band after its 'follow' state ended (7 s), not while in it.
        assert band["first_violation_s"] > 7.0
        assert run["message"].startswith("wall_distance failed by")
        assert "(required: without it the run scores 0)" in run["message"]


def test_the_honest_wall_follower_still_passes_the_corridor(corridor: dict[str, Any]) -> None:
    assert [r["status"] for r in _runs(corridor, "honest", "corridor-wall-follow")] == [
        "passed"
    ] * 3


@pytest.fixture(scope="module")
def nothing(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    root = tmp_path_factory.mktemp("nothing")
    folder = _class(root, "class", idle=DOES_NOTHING)
    specs = sorted(TEACHER.glob("*/test.yaml"))
    assert len(specs) == 3
    return _grade(folder, *specs)


def test_a_mission_that_does_nothing_but_succeed_scores_0_on_every_shipped_test(
    nothing: dict[str, Any],
) -> None:
    tests = {r["test"] for r in nothing["results"]}
    assert tests == {"corridor-wall-follow", "line-track-lap", "square-50cm"}
    for test in tests:
        for run in _runs(nothing, "idle", test):
            assert run["status"] == "failed", run["message"]
            assert _verdict(run, "outcome")["passed"]  # it did end in success
            assert run["score"] == 0.0
    assert [s["score"] for s in nothing["students"]] == [0.0]


def test_tones_played_before_the_start_do_not_count(tmp_path: Path) -> None:
    spec = tmp_path / "beeps.yaml"
    spec.write_text(TONES_SPEC, encoding="utf-8")
    report = _grade(_class(tmp_path, "class", early=BEEPS_BEFORE_ITS_START), spec)
    [run] = _runs(report, "early", "four-beeps")
    tones = _verdict(run, "tones")
    assert (tones["passed"], tones["detail"]) == (False, "4 tones too few: 0 tones played")
    assert run["record"]["sim"]["tones"] == []


def test_corners_of_two_45_degree_rotations_are_four_turns(tmp_path: Path) -> None:
    spec = tmp_path / "corners.yaml"
    spec.write_text(CORNERS_SPEC, encoding="utf-8")
    folder = _class(tmp_path, "class", halves=HALF_CORNERS)
    report = _grade(folder, spec, TEACHER / "square" / "test.yaml")
    for test in ("four-corners", "square-50cm"):
        for run in _runs(report, "halves", test):
            assert run["status"] == "passed", run["message"]
            assert _verdict(run, "turns")["detail"].startswith("4 turns (")
