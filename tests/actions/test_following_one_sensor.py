"""follow_line with one downward sensor (a SPIKE colour sensor): following the tape's edge."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from helpers import write_track

from roboscript.actions.following import _edge_position
from roboscript.mission.runner import MissionRunner
from roboscript.mission.yaml_loader import parse_yaml_mission
from roboscript.robot import Robot
from roboscript.sim.geometry import closest_point, heading_vector
from roboscript.sim.world import load_world

SENSOR_AHEAD_MM = 80.0  # where the simulated hub's colour sensor looks, ahead of the centre


def follow(
    world: str, edge: str, duration_s: float
) -> tuple[MissionRunner, list[tuple[float, float, float]]]:
    """Run follow_line on spike-prime; the colour sensor's (x, y) and the heading each tick."""
    spec, _ = parse_yaml_mission(
        f"""
states:
  follow:
    do: {{follow_line: {{speed: 10 cm/s, edge: {edge}, duration: {duration_s} s}}}}
    on: {{done: end, failed: lost}}
  end: {{final: success}}
  lost: {{final: failure}}
"""
    )
    samples: list[tuple[float, float, float]] = []
    with Robot.connect("spike-prime", world=world, seed=1) as bot:
        runner = MissionRunner(spec, bot.capabilities, gains=bot.profile.gains)
        bot.scheduler.add(runner)

        def sample(now: float, dt: float) -> None:
            body = bot.simulation.body
            fx, fy = heading_vector(body.heading_deg)
            samples.append(
                (
                    body.x_mm + fx * SENSOR_AHEAD_MM,
                    body.y_mm + fy * SENSOR_AHEAD_MM,
                    body.heading_deg,
                )
            )

        bot.scheduler.add(sample, "after")
        bot.scheduler.run(until=lambda: runner.finished, max_duration_s=90)
    return runner, samples


def test_one_sensor_follows_a_curved_track_through_every_heading(tmp_path: Path) -> None:
    track = write_track(tmp_path / "track.yaml")
    segments = load_world(str(track)).lines[0].segments
    runner, samples = follow(str(track), "left", 40)
    assert runner.result.outcome == "success", runner.result.reason
    gaps = [
        min(math.dist(closest_point(x, y, s), (x, y)) for s in segments) for x, y, _ in samples[50:]
    ]
    assert max(gaps) < 25.0  # the sensor never leaves the 20 mm tape's edge by more than 15 mm
    assert {int(h // 90) for _, _, h in samples} == {0, 1, 2, 3}


@pytest.mark.parametrize(("edge", "side"), [("left", -1.0), ("right", 1.0), ("center", -1.0)])
def test_the_sensor_rides_the_edge_it_is_asked_for(tmp_path: Path, edge: str, side: float) -> None:
    world = tmp_path / "straight.yaml"
    world.write_text(
        "world: straight\nstart: {x: 0 mm, y: 0 mm, heading: 0 deg}\n"
        "lines:\n  - {polyline: [[0 mm, -100 mm], [0 mm, 3 m]], width: 20 mm}\n",
        encoding="utf-8",
    )
    runner, samples = follow(str(world), edge, 8)
    assert runner.result.outcome == "success", runner.result.reason
    settled = [x for x, _, _ in samples[150:]]  # the tape runs north: left is -x
    mean_x = sum(settled) / len(settled)
    assert 3.0 < side * mean_x < 15.0  # on the tape's edge (10 mm from its centre line)


def test_an_edge_position_is_zero_on_the_edge_and_signed_towards_the_turn() -> None:
    threshold = 511.5
    assert _edge_position(threshold, threshold, "left") == 0.0
    assert _edge_position(1023.0, threshold, "left") == pytest.approx(-1.0)  # on the tape
    assert _edge_position(200.0, threshold, "left") == pytest.approx(0.609, abs=0.001)
    assert _edge_position(200.0, threshold, "right") == pytest.approx(-0.609, abs=0.001)
    assert _edge_position(100.0, threshold, "left") is None  # bare floor: the line is lost
