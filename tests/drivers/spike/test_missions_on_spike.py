"""Missions a SPIKE class writes, run end to end on the simulated hub through the command line."""

from __future__ import annotations

import json
from pathlib import Path

from helpers import MISSIONS, run_cli


def _run(*args: str, cwd: Path | None = None) -> dict[str, object]:
    result = run_cli("run", *args, "--robot", "spike-prime", "--json", cwd=cwd)
    assert result.returncode == 0, result.stderr
    summary: dict[str, object] = json.loads(result.stdout)
    return summary


def test_line_lap_follows_the_tape_round_both_bends_with_the_colour_sensor() -> None:
    summary = _run(str((MISSIONS / "line_lap.yaml").relative_to(MISSIONS.parent)))
    assert summary["outcome"] == "success"
    sim = summary["sim"]
    assert isinstance(sim, dict)
    path = sim["path"]
    xs = [sample[1] for sample in path]
    ys = [sample[2] for sample in path]
    # Round the east bend (x near 900), along the north straight and into the west bend.
    assert max(xs) > 850 and max(ys) > 350 and min(xs) < -850
    assert sim["distance_travelled_mm"] > 3500


PYTHON_MISSION = '''
from roboscript import Drive, Mission, state


class FindTheTape(Mission):
    """Drive across the floor until the colour sensor sees the dark tape."""

    robot = "spike-prime"

    go = state(
        Drive(distance_mm=600, speed_mm_s=100),
        initial=True,
        when=[("on_tape", "found")],
        on_done="missed",
        on_failed="missed",
    )
    found = state(final="success")
    missed = state(final="failure")

    def on_tape(self) -> bool:
        return self.color.reflection < 40 and self.color.name == "black"
'''

WORLD = """world: tape-ahead
lines:
  - {polyline: [[-300, 300], [300, 300]], width: 20 mm}
"""


def test_a_python_mission_reading_the_reflection_runs_on_spike_prime(tmp_path: Path) -> None:
    (tmp_path / "find_tape.py").write_text(PYTHON_MISSION)
    (tmp_path / "tape.yaml").write_text(WORLD)
    summary = _run("find_tape.py", "--world", "tape.yaml", cwd=tmp_path)
    assert summary["outcome"] == "success"
    sim = summary["sim"]
    assert isinstance(sim, dict)
    # The sensor is 80 mm ahead of the centre: the tape at y = 300 is seen at y ~ 210.
    assert 180 < sim["final_pose"]["y_mm"] < 260
