"""The built-in worlds with a robot in them: the maze can be left, the track can be lapped,
and a seeded run in either gives the same ``run --json`` byte for byte."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from helpers import run_cli

from roboscript.mission.runner import MissionRunner
from roboscript.mission.yaml_loader import parse_yaml_mission
from roboscript.robot import Robot
from roboscript.sim.world import load_world

# At every cell: right if open, else straight on, else turn left and look again.
MAZE_RIGHT_HAND = """
mission: maze-right-hand
world: maze
initial: look
states:
  look:
    do: {wait: {duration: 200 ms}}
    on:
      done:
        - {if: "side_range.distance_cm > 35", goto: turn_right}
        - {if: "range.distance_cm > 35", goto: step}
        - {goto: turn_left}
  turn_right:
    do: {rotate: {angle: 90 deg, turn_rate: 60 deg/s}}
    on: {done: step, failed: lost}
  turn_left:
    do: {rotate: {angle: -90 deg, turn_rate: 60 deg/s}}
    on: {done: look, failed: lost}
  step:
    do: {drive: {distance: 50 cm, speed: 15 cm/s}}
    on:
      done:
        - {if: "visits.step >= 23", goto: out}
        - {goto: look}
      failed: lost
    when:
      - {if: "bumper.any", goto: lost}
  out:
    do: {play_tone: {frequency: 880 Hz, duration: 300 ms}}
    final: success
  lost:
    final: failure
"""

ONE_LAP = """
mission: one-lap
world: line-track
initial: follow
states:
  follow:
    do: {follow_line: {speed: 12 cm/s, duration: 40 s}}
    on: {done: lap, failed: lost}
  lap:
    do: {play_tone: {frequency: 880 Hz, duration: 200 ms}}
    final: success
  lost:
    final: failure
"""


def run_mission(text: str, world: str, seed: int) -> tuple[MissionRunner, list[tuple[float, ...]]]:
    spec, _ = parse_yaml_mission(text)
    with Robot.connect("mirto", world=world, seed=seed) as bot:
        runner = MissionRunner(spec, bot.capabilities, gains=bot.profile.gains)
        bot.scheduler.add(runner)
        bot.scheduler.run(until=lambda: runner.finished, max_duration_s=300)
        return runner, list(bot.simulation.log.path)


@pytest.mark.parametrize("seed", [1, 2])
def test_a_right_hand_rule_leads_the_robot_out_of_the_maze(seed: int) -> None:
    runner, path = run_mission(MAZE_RIGHT_HAND, "maze", seed)
    assert runner.result.outcome == "success", runner.result.reason
    exit_region = load_world("maze").regions["exit"]
    assert any(exit_region.contains(x, y) for _, x, y, _ in path)


def test_following_the_line_goes_round_the_track_and_back_to_the_start() -> None:
    runner, path = run_mission(ONE_LAP, "line-track", 1)
    assert runner.result.outcome == "success", runner.result.reason
    regions = load_world("line-track").regions
    visited = [name for _, x, y, _ in path for name in regions if regions[name].contains(x, y)]
    order = [name for i, name in enumerate(visited) if i == 0 or visited[i - 1] != name]
    assert order[:5] == ["start-zone", "east-curve", "lap-check", "west-curve", "start-zone"]


@pytest.mark.parametrize(("name", "text"), [("maze", MAZE_RIGHT_HAND), ("lap", ONE_LAP)])
def test_a_seeded_run_prints_the_same_json_byte_for_byte(
    tmp_path: Path, name: str, text: str
) -> None:
    mission = tmp_path / f"{name}.yaml"
    mission.write_text(text, encoding="utf-8")
    first = run_cli("run", str(mission), "--json", "--seed", "4")
    second = run_cli("run", str(mission), "--json", "--seed", "4")
    assert first.returncode == 0, first.stderr
    assert first.stdout == second.stdout
    other = run_cli("run", str(mission), "--json", "--seed", "5")
    assert json.loads(other.stdout)["sim"]["path"] != json.loads(first.stdout)["sim"]["path"]
