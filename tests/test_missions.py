"""Every example in missions/ loads cleanly and runs to success on the simulator."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml
from helpers import MISSIONS, run_cli

from roboscript.profiles import BUILTIN_PROFILES

# Python missions sit beside their YAML twins; behaviours live in missions/behaviours/.
EXAMPLES = sorted([*MISSIONS.glob("*.yaml"), *MISSIONS.glob("*.py")])


def test_there_are_examples() -> None:
    assert len(EXAMPLES) >= 2


@pytest.mark.parametrize("mission", EXAMPLES, ids=lambda p: p.name)
def test_example_runs_to_success_on_the_simulator(mission: Path) -> None:
    result = run_cli("run", str(mission.relative_to(MISSIONS.parent)), "--json")
    assert result.returncode == 0, result.stderr
    summary = json.loads(result.stdout)
    assert summary["outcome"] == "success", summary["reason"]
    assert "sim" in summary


def _robot_of(mission: Path) -> str:
    """The robot an example is written for (missions without ``robot:`` run on mirto)."""
    if mission.suffix == ".py":
        return "mirto"
    named = yaml.safe_load(mission.read_text(encoding="utf-8")).get("robot")
    return str(named) if named else "mirto"


def test_every_built_in_robot_has_an_example_that_runs_on_it() -> None:
    covered = {_robot_of(mission) for mission in EXAMPLES}
    assert set(BUILTIN_PROFILES) <= covered, set(BUILTIN_PROFILES) - covered
