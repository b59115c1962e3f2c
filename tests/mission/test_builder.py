"""The mission builder: one set of rules for both syntaxes, and every YAML/Python twin in
``missions/`` building the identical spec."""

from __future__ import annotations

import math
import random
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from helpers import MISSIONS

from roboscript.actions import ACTIONS
from roboscript.errors import MissionError
from roboscript.inputs.source import Location
from roboscript.mission import load_mission
from roboscript.mission.builder import MissionBuilder, MissionProblemsError, action_params
from roboscript.mission.guards import GuardEnv
from roboscript.mission.spec import ActionSpec, MissionSpec, TransitionSpec
from roboscript.mission.yaml_loader import parse_yaml_mission

TWINS = sorted(p for p in MISSIONS.rglob("*.py") if p.with_suffix(".yaml").exists())

# --------------------------------------------------------------------- comparing conditions


class _Env(GuardEnv):
    """One moment of a run: sensor values and visit counts."""

    def __init__(self, values: dict[tuple[str, str | None], float | bool], visits: dict[str, int]):
        self.values = values
        self.counts = visits

    def sensor(self, root: str, attr: str | None) -> float | bool:
        return self.values[(root, attr)]

    def visits(self, state: str) -> int:
        return self.counts.get(state, 0)


def _moments(states: list[str], count: int = 300) -> list[_Env]:
    """Seeded moments, with distances close to the values missions compare against."""
    rng = random.Random(16)
    distances_mm = [0.0, 100.0, 199.9, 200.0, 249.9, 250.0, 250.1, 300.0, 1000.0, math.inf]
    moments = []
    for _ in range(count):
        values: dict[tuple[str, str | None], float | bool] = {}
        for root in ("range", "side_range"):
            mm = rng.choice(distances_mm)
            values[(root, "distance_mm")] = mm
            values[(root, "distance_cm")] = mm / 10
        left, right = rng.random() < 0.3, rng.random() < 0.3
        values.update({("bumper", "left"): left, ("bumper", "right"): right})
        values[("bumper", "any")] = left or right
        for side in ("left", "center", "right"):
            values[("line", side)] = rng.choice([0.0, 300.0, 700.0, 1023.0])
        values[("line", "any")] = rng.random() < 0.5
        for name in ("heading_deg", "elapsed", "state_time"):
            values[(name, None)] = rng.choice([0.0, 1.0, 45.0, 90.0, 181.0])
        moments.append(_Env(values, {s: rng.randrange(0, 6) for s in states}))
    return moments


def _condition(guard: Any, moments: list[_Env]) -> tuple[Any, ...]:
    """A condition by what it means: what it reads and what it says at many moments.

    Its text is left out: a Python twin names a method (``bumper_hit``) where YAML writes the
    expression (``bumper.any``).
    """
    if guard is None:
        return ("always",)
    return (
        "condition",
        frozenset(guard.capabilities),
        tuple(guard(env) for env in moments),
    )


# ------------------------------------------------------------------------- the built spec


def _value(value: Any, moments: list[_Env]) -> Any:
    if callable(value) and hasattr(value, "capabilities"):
        return _condition(value, moments)
    if isinstance(value, float | int) and not isinstance(value, bool):
        return ("number", type(value).__name__, value)  # 500 and 500.0 differ here
    return value


def _action(action: ActionSpec | None, moments: list[_Env]) -> Any:
    if action is None:
        return None
    made = action.factory()
    return {
        "name": action.name,
        "kwargs": [(k, _value(v, moments)) for k, v in action.kwargs.items()],
        "requires": action.requires,
        "bounded": action.bounded,
        "inner": _mission(action.inner) if action.inner is not None else None,
        # What runs on each entry: the same class, holding the same parameter values.
        "makes": type(made).__name__,
        "holds": [
            (p.kwarg, _value(getattr(made, p.kwarg), moments))
            if not callable(getattr(made, p.kwarg))
            else (p.kwarg, _condition(getattr(made, p.kwarg), moments))
            for p in type(made).params
            if hasattr(made, p.kwarg)
        ]
        if action.name in ACTIONS
        else None,
    }


def _transitions(items: tuple[TransitionSpec, ...], moments: list[_Env]) -> Any:
    return [(t.target, _condition(t.guard, moments)) for t in items]


def _mission(spec: MissionSpec) -> dict[str, Any]:
    """Everything a built mission holds, but where it was written (paths and locations)."""
    moments = _moments(list(spec.states))
    return {
        "name": spec.name,
        "description": spec.description,
        "initial": spec.initial,
        "robot": spec.robot,
        "world": spec.world,
        "requires": spec.requires(),
        "states": [
            {
                "name": state.name,
                "description": state.description,
                "action": _action(state.action, moments),
                "during": [_action(a, moments) for a in state.during],
                "on": [(o, _transitions(ts, moments)) for o, ts in state.on.items()],
                "when": _transitions(state.when, moments),
                "timeout_s": _value(state.timeout_s, moments),
                "final": state.final,
            }
            for state in spec.states.values()
        ],
    }


def test_the_twins_are_found() -> None:
    assert {p.stem for p in TWINS} >= {"square", "bump_and_turn", "plen_walk"}


@pytest.mark.parametrize("twin", TWINS, ids=lambda p: p.name)
def test_a_yaml_mission_and_its_python_twin_build_the_identical_spec(twin: Path) -> None:
    python_spec, python_warnings = load_mission(twin)
    yaml_spec, yaml_warnings = load_mission(twin.with_suffix(".yaml"))
    assert _mission(python_spec) == _mission(yaml_spec)
    assert [w.message for w in python_warnings] == [w.message for w in yaml_warnings]


def test_the_comparison_sees_a_changed_parameter_and_a_changed_condition(tmp_path: Path) -> None:
    # The twins test could not pass by comparing too little.
    square = (MISSIONS / "square.yaml").read_text(encoding="utf-8")
    yaml_spec, _ = load_mission(MISSIONS / "square.yaml")
    for old, new in [
        ("rotate: {angle: 90 deg}", "rotate: {angle: 90 deg, turn_rate: 60 deg/s}"),
        ('"visits.side >= 4"', '"visits.side >= 3"'),
        ('"bumper.any"', '"bumper.left"'),
        ("timeout: 10 s", "timeout: 12 s"),
    ]:
        assert old in square
        changed, _ = parse_yaml_mission(square.replace(old, new), "square.yaml")
        assert _mission(changed) != _mission(yaml_spec), new


# ------------------------------------------------------------------------------- the rules


def test_every_parameter_is_in_the_spec_with_its_default_and_quantities_are_floats() -> None:
    kwargs, problems = action_params(ACTIONS["rotate"], {"angle": 90})
    assert problems == []
    assert kwargs == {"angle_deg": 90.0, "turn_rate_deg_s": 90.0}
    assert all(type(v) is float for v in kwargs.values())
    kwargs, _ = action_params(ACTIONS["drive"], {"distance": "50 cm", "speed": "15 cm/s"})
    assert list(kwargs.items()) == [
        ("distance_mm", 500.0),
        ("speed_mm_s", 150.0),
        ("duration_s", None),
    ]


def test_a_python_action_takes_the_same_conversion() -> None:
    from roboscript import Drive

    built = MissionBuilder("m.py").action(
        ACTIONS["drive"],
        {"distance": 500, "speed": 150, "duration": None},
        Location("m.py", 3, 5),
        frozenset({"a"}),
        instance=Drive(distance_mm=500, speed_mm_s=150),
    )
    assert built is not None
    assert list(built.kwargs.items()) == [
        ("distance_mm", 500.0),
        ("speed_mm_s", 150.0),
        ("duration_s", None),
    ]
    assert all(type(v) is float for v in list(built.kwargs.values())[:2])


def test_parameter_problems_are_the_same_for_both_syntaxes() -> None:
    _, problems = action_params(ACTIONS["drive"], {"distnce": 3})
    assert problems[0][:3] == (
        "distnce",
        "'drive' has no parameter 'distnce'",
        "did you mean 'distance'?",
    )
    _, problems = action_params(ACTIONS["rotate"], {})
    assert problems == [
        ("", "'rotate' needs 'angle' (how far to turn (positive = right))", None, None)
    ]
    # read from an object its constructor checked, a missing parameter is not the student's
    assert action_params(ACTIONS["rotate"], {}, written=False)[1] == []


@pytest.mark.parametrize(
    ("seconds", "expected"),
    [(2, 2.0), (0.5, 0.5), (None, None), (0, "error"), (-1, "error"), (True, "error")],
)
def test_a_timeout_is_a_positive_number_of_seconds(seconds: Any, expected: Any) -> None:
    build = MissionBuilder("m")
    value = build.timeout("wait", "timeout", seconds, Location("m", 4, 14))
    if expected == "error":
        assert value is None
        assert [p.format() for p in build.problems] == [
            f"m:4:14: error: state 'wait': timeout is a positive number of seconds, got {seconds!r}"
        ]
    else:
        assert value == expected and type(value) is type(expected) and build.problems == []


@pytest.mark.parametrize(
    ("value", "expected"),
    [
        (True, "success"),
        ("success", "success"),
        ("failure", "failure"),
        (False, None),
        (None, None),
    ],
)
def test_final_outcomes(value: Any, expected: str | None) -> None:
    build = MissionBuilder("m")
    assert build.final("end", value, Location("m", 1, 1)) == expected
    assert build.problems == []


def test_a_wrong_final_outcome_reads_the_same_in_both_syntaxes(
    write_mission: Callable[..., Path],
) -> None:
    yaml_path = write_mission(
        "initial: go\nstates:\n  go: {do: stop, on: {done: end}}\n  end: {final: sucess}\n"
    )
    python_path = write_mission(
        "from roboscript import Mission, Stop, state\n\n\n"
        "class M(Mission):\n"
        "    go = state(Stop(), initial=True, on_done='end')\n"
        "    end = state(final='sucess')\n",
        "m.py",
    )
    found = []
    for path in (yaml_path, python_path):
        with pytest.raises(MissionProblemsError) as info:
            load_mission(path)
        found.append(info.value.message)
    assert found == ["state 'end': final is 'success' or 'failure', got 'sucess'"] * 2


def test_the_description_is_the_same_text_however_it_was_written() -> None:
    spec, _ = parse_yaml_mission(
        "description: >\n  Two lines\n  folded.\ninitial: a\nstates:\n  a: {final: success}\n"
    )
    assert spec.description == "Two lines folded."


def test_an_unknown_target_has_a_did_you_mean() -> None:
    build = MissionBuilder("m")
    assert build.target("cornr", frozenset({"corner", "side"}), Location("m", 2, 3)) is None
    assert build.problems[0].format() == (
        "m:2:3: error: there is no state 'cornr' (did you mean 'corner'?)"
    )


def test_finish_raises_every_problem_with_the_first_error_first() -> None:
    build = MissionBuilder("m")
    build.problem("second", Location("m", 5, 1))
    build.problem("first", Location("m", 2, 1))
    with pytest.raises(MissionError) as info:
        build.finish(None)
    assert info.value.message == "first"
    assert [p.message for p in info.value.problems] == ["first", "second"]  # type: ignore[attr-defined]
