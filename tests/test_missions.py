"""Every example in missions/ loads cleanly and runs to success on the simulator."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from helpers import MISSIONS, run_cli

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
