"""follow_wall and follow_line: host-side PID, on firmware-PID and host-PID robots."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from helpers import write_track

from roboscript.mission.runner import MissionRunner
from roboscript.mission.yaml_loader import parse_yaml_mission
from roboscript.robot import Robot
from roboscript.sim.geometry import Segment, closest_point

ROBOTS = ["mirto", "asip-basic"]


def run(
    robot: str, world: str, mission: str, seed: int = 1, sample: object = None
) -> MissionRunner:
    spec, _ = parse_yaml_mission(mission)
    with Robot.connect(robot, world=world, seed=seed) as bot:
        runner = MissionRunner(spec, bot.capabilities, gains=bot.profile.gains)
        bot.scheduler.add(runner)
        if sample is not None:
            bot.scheduler.add(lambda now, dt: sample(bot, runner, now), "after")  # type: ignore[operator]
        bot.scheduler.run(until=lambda: runner.finished, max_duration_s=90)
    return runner


WALL = """
states:
  follow:
    do: {follow_wall: {side: right, distance: 20 cm, speed: 12 cm/s, duration: 20 s}}
    on: {done: end, failed: lost}
  end: {final: success}
  lost: {final: failure}
"""


@pytest.mark.parametrize("robot", ROBOTS)
@pytest.mark.parametrize("seed", [1, 2])
def test_follow_wall_holds_20_cm_within_2_cm_after_settling(robot: str, seed: int) -> None:
    gaps: list[float] = []

    def sample(bot: Robot, runner: MissionRunner, now: float) -> None:
        body = bot.simulation.body
        if runner.start_time_s and now - runner.start_time_s > 8.0:
            # true gap between the right sensor (80 mm right of centre) and the wall at x=300
            right = math.radians(body.heading_deg + 90.0)
            gaps.append(300.0 - (body.x_mm + 80.0 * math.sin(right)))

    runner = run(robot, "corridor", WALL, seed, sample)
    assert runner.result.outcome == "success", runner.result.reason
    assert len(gaps) > 500
    assert min(gaps) >= 180.0 and max(gaps) <= 220.0, (min(gaps), max(gaps))


def test_follow_wall_without_a_wall_fails_lost_wall() -> None:
    runner = run("mirto", "empty", WALL)
    assert runner.result.outcome == "failure"
    assert runner.result.reason == (
        "ended in the failure state 'lost' after follow_wall failed in state 'follow': lost wall"
    )


def test_follow_wall_on_the_side_the_sensor_does_not_face_is_not_supported() -> None:
    runner = run("mirto", "corridor", WALL.replace("side: right", "side: left"))
    assert runner.result.reason is not None
    assert "not supported: this robot's side sensor faces right" in runner.result.reason


LINE = """
states:
  follow:
    do: {follow_line: {speed: 10 cm/s, duration: 45 s}}
    on: {done: end, failed: lost}
  end: {final: success}
  lost: {final: failure}
"""


@pytest.mark.parametrize("robot", ROBOTS)
def test_follow_line_completes_a_curved_track(robot: str, tmp_path: Path) -> None:
    track = write_track(tmp_path / "track.yaml")
    from roboscript.sim.world import load_world

    segments: list[Segment] = list(load_world(str(track)).lines[0].segments)
    offsets: list[float] = []
    headings: list[float] = []

    def sample(bot: Robot, runner: MissionRunner, now: float) -> None:
        body = bot.simulation.body
        nearest = min(
            math.dist(closest_point(body.x_mm, body.y_mm, s), (body.x_mm, body.y_mm))
            for s in segments
        )
        offsets.append(nearest)
        headings.append(body.heading_deg)

    runner = run(robot, str(track), LINE, 1, sample)
    assert runner.result.outcome == "success", runner.result.reason
    assert max(offsets) < 40.0  # never more than 4 cm off the tape's centre line
    # a full lap turns through every heading
    assert {int(h // 90) for h in headings} == {0, 1, 2, 3}


def test_follow_line_off_the_line_fails_lost_line() -> None:
    runner = run("asip-basic", "empty", LINE)
    assert runner.result.reason == (
        "ended in the failure state 'lost' after follow_line failed in state 'follow': lost line"
    )


@pytest.mark.parametrize("robot", ROBOTS)
def test_follow_line_into_a_wall_fails_stalled(robot: str, tmp_path: Path) -> None:
    world = tmp_path / "dead-end.yaml"
    world.write_text(
        "world: dead-end\n"
        "start: {x: 0 mm, y: 0 mm, heading: 0 deg}\n"
        "lines:\n  - {polyline: [[0 mm, -300 mm], [0 mm, 2 m]], width: 20 mm}\n"
        "walls:\n  - segment: [[-500 mm, 400 mm], [500 mm, 400 mm]]\n",
        encoding="utf-8",
    )
    ends: list[float] = []

    def sample(bot: Robot, runner: MissionRunner, now: float) -> None:
        if runner.finished and not ends:
            ends.append(now)

    runner = run(robot, str(world), LINE, 1, sample)
    assert runner.result.reason == (
        "ended in the failure state 'lost' after follow_line failed in state 'follow': stalled"
    )
    assert ends and ends[0] < 10.0  # about a second after meeting the wall, not the 45 s bound
