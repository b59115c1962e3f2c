"""The closed sets (outcomes, statuses, parameter kinds) are one list each, used everywhere."""

from __future__ import annotations

import importlib
from typing import get_args

import pytest

from roboscript.actions import ACTIONS
from roboscript.actions.base import ACTION_OUTCOMES, PARAM_KINDS, Outcome, OutcomeName
from roboscript.grading import world_host
from roboscript.grading.junit import junit_kind
from roboscript.grading.record import RUN_STATUSES, RunStatus
from roboscript.mission.runner import MISSION_OUTCOMES, MissionOutcome


def _dimensions() -> set[str]:
    for name in ("roboscript.inputs.quantities", "roboscript.mission.quantities"):
        try:
            return set(importlib.import_module(name).DIMENSIONS)
        except ModuleNotFoundError:
            continue
    raise AssertionError("no quantities module")


def test_action_outcomes_are_the_outcome_enum() -> None:
    assert ACTION_OUTCOMES == get_args(OutcomeName) == tuple(o.value for o in Outcome)


def test_parameter_kinds_are_the_quantities_and_four_others() -> None:
    assert set(PARAM_KINDS) == _dimensions() | {"text", "choice", "guard", "color"}
    used = {param.kind for action in ACTIONS.values() for param in action.params}
    assert used <= set(PARAM_KINDS)


def test_mission_outcomes_are_one_list() -> None:
    assert MISSION_OUTCOMES == get_args(MissionOutcome) == ("success", "failure", "error")
    assert world_host.MISSION_OUTCOMES is MISSION_OUTCOMES


@pytest.mark.parametrize("status", RUN_STATUSES)
def test_every_run_status_has_a_junit_element(status: str) -> None:
    expected = {"passed": None, "failed": "failure", "missing": "skipped"}.get(status, "error")
    assert junit_kind(status) == expected


def test_run_statuses_are_the_documented_eight() -> None:
    assert get_args(RunStatus) == RUN_STATUSES
    documented = ["passed", "failed", "too slow", "timeout", "hung", "crashed", "invalid"]
    assert list(RUN_STATUSES) == [*documented, "missing"]
