"""Hand-made run records and the shared helpers of the expectation tests."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from roboscript.errors import SpecError
from roboscript.grading.expectations import (
    CheckFunction,
    Expectation,
    PathVisits,
    Rule,
    RunTargets,
    Waypoint,
    evaluate,
)
from roboscript.grading.record import Collision, RunRecord, Tone, Verdict
from roboscript.grading.spec import TestSpec, load_test_spec
from roboscript.sim.geometry import Segment, heading_vector
from roboscript.sim.world import Region, World

ROOM = World(
    "room",
    walls=(Segment(300, -200, 300, 3000), Segment(-300, -200, -300, 3000)),
    regions={
        "a": Region("a", (0.0, 500.0), radius_mm=100.0),
        "b": Region("b", (0.0, 1000.0), radius_mm=100.0),
        "pit": Region(
            "pit", (600.0, 500.0), points=((500, 400), (700, 400), (700, 600), (500, 600))
        ),
        "dot": Region("dot", (0.0, 2000.0), radius_mm=5.0),
    },
)


def _record(
    path: list[tuple[float, float, float, float]],
    *,
    states: tuple[tuple[float, str], ...] = ((0.0, "go"),),
    tones: tuple[Tone, ...] = (),
    collisions: tuple[Collision, ...] = (),
    outcome: str = "success",
    final_state: str = "done",
    reason: str | None = None,
    world: World | None = ROOM,
) -> RunRecord:
    """A run of the mission ``m`` along ``path`` in ``world`` (the room: walls 30 cm either
    side of x = 0, regions 'a', 'b', 'pit' and 'dot'), ending at the path's last sample."""
    last = path[-1]
    return RunRecord.simulated(
        mission="m",
        robot="mirto",
        world_name=ROOM.name,
        seed=1,
        outcome=outcome,
        final_state=final_state,
        reason=reason,
        duration_s=last[0],
        states=states,
        path=tuple(path),
        tones=tones,
        collisions=collisions,
        final_pose=(last[1], last[2], last[3]),
        world=world,
    )


def _sim_changed(record: RunRecord, **changes: object) -> RunRecord:
    """``record`` with what the simulator saw changed (``path``, ``seed``...)."""
    return replace(record, sim=replace(record.simulation, **changes))


def _north(t_end: float, x: float = 0.0, speed_mm_s: float = 100.0) -> list[tuple[float, ...]]:
    """A robot driving north along x at ``speed``, sampled every 0.1 s."""
    steps = round(t_end / 0.1)
    return [(round(i * 0.1, 3), x, round(i * 0.1 * speed_mm_s, 1), 0.0) for i in range(steps + 1)]


def _judge(rule: Rule, record: RunRecord) -> Verdict:
    return evaluate(Expectation(rule), record)


def _tones(*pairs: tuple[float, float]) -> tuple[Tone, ...]:
    return tuple(Tone(t, f, 0.2) for t, f in pairs)


def _drifting_right() -> list[tuple[float, float, float, float]]:
    """North at x = 0 for 4 s, then drifting east at 50 mm/s towards the wall at x = 300."""
    path = []
    for i in range(81):
        t = round(i * 0.1, 3)
        x = 0.0 if t <= 4.0 else round((t - 4.0) * 50.0, 1)
        path.append((t, x, round(t * 100.0, 1), 0.0))
    return path


Pose = tuple[float, float, float]


def _square(
    turn_deg: float = 90.0,
    *,
    side_mm: float = 500.0,
    start: Pose = (0.0, 0.0, 0.0),
    sides: int = 4,
    rate_deg_s: float = 90.0,
    pause_s: float = 0.5,
) -> list[tuple[float, float, float, float]]:
    """A square driven at 100 mm/s, sampled every 0.1 s: a side, a pause, a turn on the spot of
    ``turn_deg`` (positive: right), a pause, and so on. Headings are recorded 0-360 like the
    simulator's, so a left turn from north reads 351, 342, ..."""
    x, y, h = start
    path = [(0.0, x, y, h % 360.0)]

    def sample() -> None:
        t = round(path[-1][0] + 0.1, 3)
        path.append((t, round(x, 3), round(y, 3), round(h % 360.0, 3)))

    for _ in range(sides):
        dx, dy = heading_vector(h)
        for _ in range(round(side_mm / 10.0)):
            x, y = x + dx * 10.0, y + dy * 10.0
            sample()
        for _ in range(round(pause_s / 0.1)):
            sample()
        steps = round(abs(turn_deg) / rate_deg_s / 0.1)
        for _ in range(steps):
            h += turn_deg / steps
            sample()
        for _ in range(round(pause_s / 0.1)):
            sample()
    return path


SQUARE = PathVisits(
    (Waypoint(500.0, 0.0), Waypoint(500.0, 500.0), Waypoint(0.0, 500.0), Waypoint(0.0, 0.0)),
    tolerance_mm=40.0,
)


def _spin_in_place(headings: list[float]) -> list[tuple[float, float, float, float]]:
    return [(round(i * 0.1, 3), 0.0, 0.0, h % 360.0) for i, h in enumerate(headings)]


def _stopped(x: float, y: float, heading: float) -> RunRecord:
    return _record([(0.0, 0.0, 0.0, 0.0), (5.0, x, y, heading)])


def _spec(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "spec.yaml"
    path.write_text(text, encoding="utf-8")
    return path


STOP_AT_WALL = """\
mission: stop-at-wall
initial: forward
states:
  forward:
    do: {drive: {distance: 3 m, speed: 15 cm/s}}
    timeout: 20 s
    on: {done: stop, failed: stop, timeout: stop}
    when:
      - {if: "range.distance_cm < 30", goto: stop}
  stop:
    do: {play_tone: {frequency: 660 Hz, duration: 300 ms}}
    final: success
"""


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


def _load(tmp_path: Path, text: str) -> TestSpec:
    path = tmp_path / "spec.yaml"
    path.write_text("test: t\n" + text, encoding="utf-8")
    return load_test_spec(path)


def _rules_and_weights(tmp_path: Path, text: str) -> list[tuple[object, float]]:
    return [(e.rule, e.weight) for e in _load(tmp_path, text).expectations]


def _targets(tmp_path: Path, text: str) -> RunTargets:
    """The run targets of the spec's first expectation."""
    targets = _load(tmp_path, text).expectations[0].targets
    assert targets is not None
    return targets


def _check_answer(tmp_path: Path, body: str, *, calls: int = 1) -> Verdict:
    checks = tmp_path / "checks.py"
    checks.write_text(
        "import itertools\n"
        "from roboscript.grading.record import Verdict\n"
        "CALLS = itertools.count()\n\n"
        "def helper():\n"
        "    raise ValueError('no lap')\n\n"
        f"def judge(run):\n    calls = next(CALLS)\n    {body}\n",
        encoding="utf-8",
    )
    expectation = Expectation(CheckFunction(str(checks), "judge", "checks.py:judge"))
    verdicts = [evaluate(expectation, _record(_north(5.0))) for _ in range(calls)]
    return verdicts[-1]


FAULT = (
    "the teacher's check returned {}; it must return True/False, (True/False, message) or a Verdict"
)


CORRIDOR_SIDE = World("right-wall", walls=(Segment(300, -200, 300, 3000),))
"""One wall, 300 mm right of the robot's line: its right sensor (80 mm out) reads 220 mm."""


def _spin(
    headings: list[float], dt_s: float = 0.1, creep_mm: float = 50.0
) -> list[tuple[float, float, float, float]]:
    """Turning on the spot through ``headings``, one sample every ``dt_s``; between samples
    with the same heading the robot creeps ``creep_mm`` east, so turns a pause apart are
    driven apart too."""
    path = []
    x = 0.0
    for i, h in enumerate(headings):
        if i and h == headings[i - 1]:
            x += creep_mm
        path.append((round(i * dt_s, 3), x, 0.0, h % 360.0))
    return path


def _left_turns(n: int) -> list[tuple[float, float, float, float]]:
    """``n`` left turns of 90 degrees at 90 deg/s, each followed by a second standing still."""
    headings: list[float] = []
    for turn in range(n):
        headings += [-90.0 * turn - 9.0 * i for i in range(10)] + [-90.0 * (turn + 1)] * 10
    return _spin(headings)


YARD = World(
    "yard",
    walls=(Segment(300, -200, 300, 3000),),
    regions={
        "pit": Region(
            "pit", (600.0, 500.0), points=((500, 400), (700, 400), (700, 600), (500, 600))
        ),
        "pond": Region("pond", (-400.0, 300.0), radius_mm=100.0),
    },
)


Samples = list[tuple[float, float, float, float]]


def _verdict(
    name: str,
    passed: bool,
    margin: str = "",
    first_violation_s: float | None = None,
    detail: str = "",
    value: float | None = None,
    unit: str = "",
    relative: float | None = None,
) -> Verdict:
    return Verdict(name, passed, margin, first_violation_s, detail, value, unit, relative)


def _same(got: Verdict, wanted: Verdict) -> None:
    assert replace(got, relative_margin=None) == replace(wanted, relative_margin=None)
    if wanted.relative_margin is None:
        assert got.relative_margin is None
    else:
        assert got.relative_margin == pytest.approx(wanted.relative_margin)


NO_PATH = _sim_changed(_record(_north(1.0)), path=())


RIGHT_90_FROM_EAST = [90.0] * 3 + [90.0 + 9.0 * i for i in range(1, 11)] + [180.0] * 4
"""Facing east, a 90° right turn at 90°/s starting at 0.2 s, then still."""


FOUR_RIGHT = (
    "4 turns (90° right at 5.5 s, 90° right at 12.5 s, 90° right at 19.5 s, 90° right at 26.5 s)"
)


# One fast 90° right turn, then a slow drift of 200° to the left at 2°/s: too slow to be a
# turn, but the heading changed all the same.
DRIFT = [0.0, *(9.0 * i for i in range(1, 11)), 90.0, 90.0, 90.0]
DRIFT += [90.0 - 0.2 * i for i in range(1, 1001)] + [-110.0] * 3


WANTED = "measured from the front of the robot straight ahead; wanted"


AHEAD = [Waypoint(500.0, 0.0), Waypoint(1500.0, 0.0), Waypoint(2000.0, 0.0)]


SLANT = [(0.0, 0.0, 0.0, 0.0)] + [(0.5 * i, 300.0 * i, 400.0 * i, 36.87) for i in range(1, 5)]
