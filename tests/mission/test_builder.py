"""The mission builder: one set of rules for both syntaxes, and every YAML/Python twin in
``missions/`` building the identical spec.
"""

from __future__ import annotations

import math
import random
import textwrap
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from helpers import MISSIONS, run_cli

from roboscript.actions import ACTIONS
from roboscript.actions.composite import Repeat
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
        (
            "",
            "'rotate' needs 'angle', how far to turn (positive = right)",
            "write `angle: 90 deg`",
            None,
        )
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
            (
                f"m:4:14: error: state 'wait': timeout is a positive number of seconds,"
                f" got {seconds!r} (write `timeout: 10 s`)"
            )
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


# -------- The builder's rules as a student meets them, message by message
#
# The mission builder's rules as a student meets them.
#
# Each test loads a whole mission, YAML or Python, and checks what the student sees: the
# parameters an action runs with, the full ``file:line:col: error: message (hint)`` of each
# mistake, and the robot capabilities the mission is said to need. A few rules only the builder's
# own API reaches (a ``repeat`` count, a problem with no place) are checked on the builder.


END = "  b: {final: success}\n"


def _yaml(states: str, head: str = "") -> tuple[MissionSpec, list[str]]:
    """A YAML mission whose first state is ``a``, with its warnings as the student reads them."""
    spec, warnings = parse_yaml_mission(f"{head}initial: a\nstates:\n{states}", "m.yaml")
    return spec, [w.format() for w in warnings]


def _yaml_errors(states: str, head: str = "") -> list[str]:
    """Every problem of a YAML mission that does not load, in the order the student sees."""
    with pytest.raises(MissionProblemsError) as info:
        parse_yaml_mission(f"{head}initial: a\nstates:\n{states}", "m.yaml")
    return [p.format() for p in info.value.problems]


def _python(write: Callable[..., Path], body: str, name: str = "m.py") -> Path:
    return write(textwrap.dedent(body), name)


def _python_errors(path: Path) -> list[str]:
    with pytest.raises(MissionProblemsError) as info:
        load_mission(path)
    return [p.format() for p in info.value.problems]


class _Moment(GuardEnv):
    """A moment of a run in which every sensor reads 0 and no state was visited."""

    def sensor(self, root: str, attr: str | None) -> float | bool:
        return 0.0

    def visits(self, state: str) -> int:
        return 0


def _state_action(spec: MissionSpec, state: str = "a") -> ActionSpec:
    action = spec.states[state].action
    assert action is not None
    return action


# ------------------------------------------------------------------- the first error raised


def test_the_raised_error_reads_as_the_first_problem_with_its_hint() -> None:
    with pytest.raises(MissionProblemsError) as info:
        parse_yaml_mission(
            "initial: a\nstates:\n  a: {do: {drive: {distnce: 3 cm}}, on: {done: b}}\n" + END,
            "m.yaml",
        )
    assert str(info.value) == (
        "m.yaml:3:20: error: 'drive' has no parameter 'distnce' (did you mean 'distance'?)"
    )
    assert info.value.hint == "did you mean 'distance'?"


# ----------------------------------------------------------------------- action parameters


def test_an_unknown_parameter_lists_the_ones_the_action_takes() -> None:
    assert _yaml_errors(
        "  a: {do: {follow_wall: {colour: left}}, timeout: 2 s, on: {timeout: b}}\n" + END
    ) == [
        (
            "m.yaml:3:26: error: 'follow_wall' has no parameter 'colour' "
            "('follow_wall' takes side, distance, speed, until, duration)"
        )
    ]


def test_an_action_with_no_parameters_has_no_list_to_offer() -> None:
    assert _yaml_errors("  a: {do: {stop: {speed: 3}}, on: {done: b}}\n" + END) == [
        "m.yaml:3:19: error: 'stop' has no parameter 'speed'"
    ]


@pytest.mark.parametrize(
    ("params", "expected"),
    [
        (
            "{walk: {steps: 2.5}}",
            "m.yaml:3:26: error: walk steps: expected a whole number, got 2.5",
        ),
        (
            "{follow_wall: {side: up, duration: 2 s}}",
            "m.yaml:3:32: error: follow_wall side: expected one of left, right, got 'up'",
        ),
        (
            "{follow_wall: {until: 5}}",
            (
                "m.yaml:3:33: error: follow_wall until: "
                'expected a condition such as "range.distance_cm < 20", got 5'
            ),
        ),
        (
            "{display: {text: [1]}}",
            "m.yaml:3:28: error: display text: expected text, got [1]",
        ),
    ],
)
def test_a_parameter_of_the_wrong_kind_is_named_with_what_it_takes(
    params: str, expected: str
) -> None:
    assert _yaml_errors(f"  a: {{do: {params}, on: {{done: b}}}}\n" + END) == [expected]


def test_a_condition_parameter_knows_the_mission_s_states() -> None:
    # visits.c reads a state that does not exist: only the mission's state names can say so
    assert _yaml_errors(
        "  a: {do: {follow_wall: {until: visits.c > 1}}, on: {done: b}}\n" + END
    ) == ["m.yaml:3:40: error: follow_wall until: 'visits.c': there is no state 'c'"]
    spec, _ = _yaml(
        "  a: {do: {follow_wall: {until: visits.b > 1}}, on: {done: b, failed: b}}\n" + END
    )
    assert _state_action(spec).kwargs["until"].states == frozenset({"b"})


@pytest.mark.parametrize(("written", "holds"), [("true", True), ("false", False)])
def test_a_yes_or_no_condition_parameter_is_the_word_it_stands_for(
    written: str, holds: bool
) -> None:
    spec, _ = _yaml(
        f"  a: {{do: {{follow_wall: {{until: {written}}}}}, on: {{done: b, failed: b}}}}\n" + END
    )
    until = _state_action(spec).kwargs["until"]
    assert (until.source, until(_Moment())) == (written, holds)


def test_text_is_kept_as_text_whatever_was_written() -> None:
    for written, kept in [("12", "12"), ("hello there", "hello there"), ("2.5", "2.5")]:
        spec, _ = _yaml(f"  a: {{do: {{display: {{text: {written}}}}}, on: {{done: b}}}}\n" + END)
        assert _state_action(spec).kwargs == {"text": kept}


def test_a_bare_number_s_warning_points_at_the_number() -> None:
    _, warnings = _yaml("  a: {do: {drive: {distance: 30}}, on: {done: b, failed: b}}\n" + END)
    assert warnings == [
        (
            "m.yaml:3:30: warning: drive distance: 30 taken as 30 mm; write `30 mm` "
            "(or did you mean 30 cm?)"
        )
    ]


# ------------------------------------------------------------ capabilities a mission needs


def test_a_condition_parameter_s_sensor_is_needed_too() -> None:
    # until comes before duration: the condition's sensor must survive the later parameters
    spec, _ = _yaml(
        "  a: {do: {follow_wall: {until: range.distance_cm < 20, duration: 3 s}},"
        " on: {done: b, failed: b}}\n" + END
    )
    assert _state_action(spec).requires == frozenset({"range", "side_range", "drive_base"})
    spec, _ = _yaml(
        "  a: {do: {wait_until: {condition: bumper.any, timeout: 3 s}},"
        " on: {done: b, timeout: b}}\n" + END
    )
    assert spec.requires() == frozenset({"bumper"})


def test_a_python_repeat_or_parallel_needs_what_its_actions_need(
    write_mission: Callable[..., Path],
) -> None:
    path = _python(
        write_mission,
        """\
        from roboscript import Drive, Mission, Parallel, PlayTone, Repeat, state


        class M(Mission):
            a = state(Repeat(Drive(distance_mm=100), 2), initial=True, on_done="c", on_failed="c")
            c = state(
                Parallel([PlayTone(frequency_hz=440)], "all"), on_done="b", on_failed="b"
            )
            b = state(final="success")
        """,
    )
    spec, _ = load_mission(path)
    assert _state_action(spec).requires == frozenset({"drive_base"})
    assert _state_action(spec, "c").requires == frozenset({"speaker"})


# --------------------------------------------------------------- a Python mission's actions


BEHAVIOUR = """\
from roboscript import Action, Mission, Param, Result, state


class Sweep(Action):
    '''Keeps its parameters under names of its own, and a setting that is no parameter.'''

    name = "sweep"
    params = (
        Param("reach", "reach_mm", "distance", "how far to reach"),
        Param("side", "side", "choice", "which side", "left", ("left", "right")),
        Param("width", "width_mm", "distance", "how wide", 100.0),
    )

    def __init__(self, reach_mm: float = 50.0, side: str = "left", width_mm: float = 100.0,
                 *, laps: int = 1) -> None:
        self.target = reach_mm
        self.laps = laps
        self.seen: list[int] = []

    def update(self, ctx):
        self.seen.append(1)
        return Result.done()


class M(Mission):
    a = state(Sweep(laps=3), initial=True, on_done="b")
    b = state(final="success")
"""


def test_a_behaviour_keeping_its_parameters_elsewhere_builds(
    write_mission: Callable[..., Path],
) -> None:
    # what the object does not hold takes the documented default; a required parameter it
    # does not hold was checked by its own constructor, not a mistake of the student's
    spec, warnings = load_mission(_python(write_mission, BEHAVIOUR))
    assert warnings == []
    assert _state_action(spec).kwargs == {"side": "left", "width_mm": 100.0}


def test_each_visit_runs_a_fresh_copy_of_the_object_the_mission_made(
    write_mission: Callable[..., Path],
) -> None:
    spec, _ = load_mission(_python(write_mission, BEHAVIOUR))
    first = _state_action(spec).factory()
    first.seen.append(7)
    second = _state_action(spec).factory()
    # the setting the student gave (laps=3) is kept, and nothing of the first visit
    assert (second.laps, second.seen) == (3, [])


# --------------------------------------------------------------------------------- parallel

PARALLEL = """\
  a:
    do:
      parallel:
        {mode}:
          - {{follow_wall: {{side: left}}}}
          - {{wait: {{duration: 2 s}}}}
    on: {{done: b}}
"""


def test_parallel_any_ends_with_its_bounded_action() -> None:
    spec, warnings = _yaml(PARALLEL.format(mode="any") + END)
    action = _state_action(spec)
    assert (action.name, action.kwargs, str(action.location), action.requires) == (
        "parallel",
        {"mode": "any", "actions": ("follow_wall", "wait")},
        "m.yaml:5:7",
        frozenset({"side_range", "drive_base"}),
    )
    assert action.factory().mode == "any"
    assert warnings == [
        (
            "m.yaml:5:7: warning: if 'parallel' fails (lost wall or stalled) in state 'a', "
            "the mission ends in failure (add 'on: {failed: STATE}' to handle it)"
        )
    ]


def test_parallel_all_never_ends_while_one_action_runs_on() -> None:
    assert _yaml_errors(PARALLEL.format(mode="all") + END) == [
        (
            "m.yaml:5:7: error: 'parallel' in state 'a' never ends as written (write"
            " `until: range.distance_cm < 20` or `duration: 10 s` in 'follow_wall', or give the"
            " state `timeout: 10 s` or a `when`)"
        ),
        (
            "m.yaml:5:7: warning: if 'parallel' fails (lost wall or stalled) in state 'a', "
            "the mission ends in failure (add 'on: {failed: STATE}' to handle it)"
        ),
    ]


def test_parallel_all_of_bounded_actions_ends() -> None:
    spec, _ = _yaml(
        "  a:\n    do:\n      parallel:\n        all:\n"
        "          - {play_tone: {frequency: 440 Hz}}\n          - {wait: {duration: 2 s}}\n"
        "    on: {done: b}\n" + END
    )
    assert _state_action(spec).bounded
    assert _state_action(spec).factory().mode == "all"


def test_a_parallel_of_two_moves_is_refused_since_each_undoes_the_other() -> None:
    errors = _yaml_errors(
        "  a:\n    do:\n      parallel:\n        all:\n"
        "          - {drive: {distance: 30 cm}}\n"
        "          - {repeat: {times: 2, do: {rotate: {angle: 90 deg}}}}\n"
        "    on: {done: b, failed: b}\n" + END
    )
    assert errors[0] == (
        "m.yaml:5:7: error: 'drive' and 'repeat' both move the wheels, and a parallel runs its"
        " actions at the same time, so each would undo what the other does (one after another,"
        " each in a state of its own; a parallel is for one move with actions that do not move"
        " the robot, such as play_tone or set_led)"
    )


# ----------------------------------------------------------------------------------- repeat


def test_repeat_once_runs_its_action_once() -> None:
    spec, _ = _yaml(
        "  a:\n    do: {repeat: {times: 1, do: {drive: {distance: 20 cm}}}}\n"
        "    on: {done: b, failed: b}\n" + END
    )
    action = _state_action(spec)
    assert (action.name, action.kwargs, str(action.location), action.requires) == (
        "repeat",
        {"times": 1, "action": "drive"},
        "m.yaml:4:10",
        frozenset({"drive_base"}),
    )
    repeat = action.factory()
    assert repeat.times == 1
    child = repeat.factory()
    assert (type(child).name, child.distance_mm) == ("drive", 200.0)


def test_repeat_of_an_endless_action_never_ends() -> None:
    assert _yaml_errors(
        "  a:\n    do: {repeat: {times: 2, do: follow_line}}\n    on: {done: b, failed: b}\n" + END
    ) == [
        (
            "m.yaml:4:10: error: 'repeat' in state 'a' never ends as written (write"
            " `until: range.distance_cm < 20` or `duration: 10 s` in 'follow_line', or give the"
            " state `timeout: 10 s` or a `when`)"
        )
    ]


@pytest.mark.parametrize("times", [0, -1, True, 1.5, "2", 10**9])
def test_the_builder_refuses_a_repeat_count_that_is_not_a_whole_number_from_1(
    times: Any,
) -> None:
    # the YAML reader checks the count before the builder; this is the builder's own guard,
    # with the rule Repeat holds
    build = MissionBuilder("m.yaml")
    child = build.action(ACTIONS["stop"], {}, Location("m.yaml", 4, 20), frozenset({"a"}))
    assert child is not None
    assert build.repeat(times, child, Location("m.yaml", 4, 10)) is None
    wrong = Repeat.times_problem(times)
    assert wrong is not None
    assert [p.format() for p in build.problems] == [
        f"m.yaml:4:10: error: {wrong.message} (write {wrong.yaml})"
    ]


# ------------------------------------------------------------------------ nested machines

INNER = """\
  a:
    do:
      initial: x
      states:
        x: {{do: {{drive: {{{param}: 30 cm}}}}{on}}}
        y: {{final: success}}
    on: {{done: b, failed: b}}
"""


def test_inner_states_run_as_one_action_needing_what_they_need() -> None:
    spec, warnings = _yaml(INNER.format(param="distance", on=", on: {done: y, failed: y}") + END)
    action = _state_action(spec)
    assert warnings == []
    assert (action.name, action.kwargs, str(action.location), action.requires) == (
        "states",
        {"mission": "a", "states": ("x", "y")},
        "m.yaml:5:7",
        frozenset({"drive_base"}),
    )
    assert spec.requires() == frozenset({"drive_base"})


def test_inner_states_are_checked_like_a_mission() -> None:
    assert _yaml_errors(INNER.format(param="distance", on="") + END) == [
        (
            "m.yaml:7:9: error: state 'x' has no way out "
            "(add 'on: {done: NEXT}', a 'when' condition, or 'final: success')"
        ),
        (
            "m.yaml:7:18: warning: if 'drive' fails (stalled) in state 'x', the mission ends in "
            "failure (add 'on: {failed: STATE}' to handle it)"
        ),
        (
            "m.yaml:8:9: error: state 'y' can never be reached from 'x' "
            "(add a transition to it, or remove it)"
        ),
    ]


def test_a_mistake_in_inner_states_is_reported_once_and_alone() -> None:
    assert _yaml_errors(INNER.format(param="distnce", on=", on: {done: y}") + END) == [
        "m.yaml:7:26: error: 'drive' has no parameter 'distnce' (did you mean 'distance'?)"
    ]


# ------------------------------------------------------------------ transitions, conditions


def test_a_target_that_is_not_a_name(write_mission: Callable[..., Path]) -> None:
    path = _python(
        write_mission,
        """\
        from roboscript import Mission, Stop, state


        class M(Mission):
            a = state(Stop(), initial=True, on_done=5)
            b = state(final="success")
        """,
    )
    assert _python_errors(path) == [f"{path}:5:45: error: expected a state name, got 5"]


@pytest.mark.parametrize(("written", "holds"), [("true", True), ("false", False)])
def test_a_yes_or_no_condition_is_the_word_it_stands_for(written: str, holds: bool) -> None:
    spec, _ = _yaml(
        f"  a: {{do: follow_line, when: [{{if: {written}, goto: b}}], timeout: 3 s,"
        " on: {timeout: b, failed: b}}\n" + END
    )
    (transition,) = spec.states["a"].when
    assert (transition.guard.source, transition.guard(_Moment())) == (written, holds)


def test_a_condition_that_is_not_text() -> None:
    assert _yaml_errors("  a: {do: stop, when: [{if: 5, goto: b}]}\n" + END) == [
        'm.yaml:3:29: error: a condition is text, e.g. if: "range.distance_cm < 20"'
    ]


# ------------------------------------------------------------------------ states, mission


def test_a_timeout_s_message_quotes_it_as_written() -> None:
    assert _yaml_errors("  a: {do: stop, timeout: -2 s, on: {done: b}}\n" + END) == [
        (
            "m.yaml:3:26: error: state 'a': timeout is a positive number of seconds, got '-2 s'"
            " (write `timeout: 10 s`)"
        )
    ]


def test_a_timeout_beyond_any_float(write_mission: Callable[..., Path]) -> None:
    path = _python(
        write_mission,
        """\
        from roboscript import Mission, Wait, state


        class M(Mission):
            a = state(Wait(duration_s=1), initial=True, timeout_s=10**400, on_done="b",
                      on_timeout="b")
            b = state(final="success")
        """,
    )
    assert _python_errors(path) == [
        f"{path}:5:59: error: state 'a': timeout_s: a number with about 401 digits is too large"
    ]


def test_a_state_keeps_its_description() -> None:
    spec, _ = _yaml("  a: {do: stop, description: '  turns about  ', on: {done: b}}\n" + END)
    assert spec.states["a"].description == "turns about"


def test_a_robot_that_is_not_a_name() -> None:
    assert _yaml_errors("  a: {final: success}\n", head="robot: 5\n") == [
        "m.yaml:1:8: error: 'robot' names a robot, e.g. robot: mirto"
    ]


def test_a_python_robot_that_is_not_a_name(write_mission: Callable[..., Path]) -> None:
    path = _python(
        write_mission,
        """\
        from roboscript import Mission, Stop, state


        class M(Mission):
            world = 5
            a = state(Stop(), initial=True, on_done="b")
            b = state(final="success")
        """,
    )
    assert _python_errors(path) == [
        f"{path}:5:13: error: 'world' names a world, e.g. world = \"square-room\""
    ]


# ---------------------------------------------------------------- the builder's own defaults


def test_a_problem_with_no_place_names_the_file() -> None:
    build = MissionBuilder("m.yaml")
    build.problem("something is wrong", None, "fix it")
    assert [p.format() for p in build.problems] == ["m.yaml: error: something is wrong (fix it)"]


def test_without_parameter_places_problems_are_at_the_action() -> None:
    build = MissionBuilder("m.yaml")
    where = Location("m.yaml", 3, 12)
    assert build.action(ACTIONS["drive"], {"distance": 30}, where, frozenset()) is not None
    assert build.action(ACTIONS["drive"], {"distnce": 3}, where, frozenset()) is None
    assert [p.format() for p in build.problems] == [
        (
            "m.yaml:3:12: warning: drive distance: 30 taken as 30 mm; write `30 mm` "
            "(or did you mean 30 cm?)"
        ),
        "m.yaml:3:12: error: 'drive' has no parameter 'distnce' (did you mean 'distance'?)",
    ]


# ------------------------------------------------------------------ the order of problems


def test_a_python_mission_s_own_mistakes_come_before_those_of_a_class_it_imports(
    write_mission: Callable[..., Path],
) -> None:
    inner = _python(
        write_mission,
        """\
        from roboscript import Mission, Stop, state


        class Inner(Mission):
            x = state(Stop(), initial=True, on_done="nowhere")
            y = state(final="success")
        """,
        "builder_inner.py",
    )
    path = _python(
        write_mission,
        """\
        from builder_inner import Inner

        from roboscript import Mission, Stop, state


        class M(Mission):
            a = state(Inner, initial=True, on_done="b")
            b = state(Stop(), on_done="elsewhere")
            c = state(final="success")
        """,
    )
    # the imported class's mistake is on an earlier line, yet the student's file comes first
    assert _python_errors(path) == [
        f"{path}:8:31: error: there is no state 'elsewhere'",
        f"{inner}:5:45: error: there is no state 'nowhere'",
    ]


def test_problems_are_in_line_then_column_order_a_whole_file_s_first() -> None:
    build = MissionBuilder("m.yaml")
    # recorded out of order, as the loaders find them
    build.problem("line 1, column 1", Location("m.yaml", 1, 1))
    build.problem("line 1", Location("m.yaml", 1))
    build.problem("the whole file", None)
    build.problem("line 2, column 9", Location("m.yaml", 2, 9))
    build.problem("line 2, column 1", Location("m.yaml", 2, 1))
    with pytest.raises(MissionProblemsError) as info:
        build.finish(None)
    assert [p.format() for p in info.value.problems] == [
        "m.yaml: error: the whole file",
        "m.yaml:1: error: line 1",
        "m.yaml:1:1: error: line 1, column 1",
        "m.yaml:2:1: error: line 2, column 1",
        "m.yaml:2:9: error: line 2, column 9",
    ]


def test_a_state_timeout_that_is_not_positive_shows_one_in_the_missions_language(
    tmp_path: Path,
) -> None:
    (tmp_path / "m.yaml").write_text(
        "mission: m\nstates:\n  go:\n    do: {drive: {distance: 50 cm}}\n    timeout: 0\n"
        "    on: {done: end, failed: end, timeout: end}\n  end: {final: success}\n",
        encoding="utf-8",
    )
    (tmp_path / "m.py").write_text(
        "from roboscript import Drive, Mission, state\n\n\nclass M(Mission):\n"
        "    go = state(Drive(distance_mm=500), initial=True, timeout_s=0, on_done='end',\n"
        "               on_failed='end', on_timeout='end')\n"
        '    end = state(final="success")\n',
        encoding="utf-8",
    )
    result = run_cli("check", "m.yaml", "m.py", cwd=tmp_path)
    assert [line for line in result.stderr.splitlines() if "error" in line] == [
        (
            "m.yaml:5:14: error: state 'go': timeout is a positive number of seconds, got 0"
            " (write `timeout: 10 s`)"
        ),
        (
            "m.py:5:64: error: state 'go': timeout_s is a positive number of seconds, got 0"
            " (write timeout_s=10)"
        ),
        "checked 2 files: 2 with errors",
    ]


# ------------------------------------------------------------- a student's file, read once


def _chained_methods(count: int) -> str:
    """A Python mission with two action classes, one of whose update() calls ``count``
    methods in a chain, the last of which sleeps."""
    steps = "".join(
        f"\n    def step{n}(self):\n        return self.step{n + 1}()\n" for n in range(count)
    )
    return (
        textwrap.dedent(
            """\
        import time

        from roboscript import Action, Mission, Result, state


        class Pause(Action):
            name = "pause"

            def update(self, ctx):
                return self.step0()
        """
        )
        + steps.replace(f"self.step{count}()", "time.sleep(1)")
        + textwrap.dedent(
            """

        class Rest(Action):
            name = "rest"

            def update(self, ctx):
                time.sleep(2)
                return Result.done()


        class M(Mission):
            go = state(Pause(), initial=True, timeout_s=5, on_done="rest", on_timeout="end")
            rest = state(Rest(), timeout_s=5, on_done="end", on_timeout="end")
            end = state(final="success")
        """
        )
    )


def test_a_student_file_of_many_methods_is_parsed_once_and_walked_in_linear_work(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # check follows update() through 200 methods to the sleep, in two classes of one file:
    # each method looked up by a fresh parse and a walk of the whole file was 200 parses
    # and 200 x the file's nodes; a file changed at load or placed by a compiler of its own
    # each parsed it again
    import ast

    text = _chained_methods(200)
    path = tmp_path / "chain.py"
    path.write_text(text, encoding="utf-8")
    file_nodes = sum(1 for _ in ast.walk(ast.parse(text)))
    parses: list[str] = []
    walked = [0]
    parse, walk = ast.parse, ast.walk

    def counted_parse(source: Any, *args: Any, **kwargs: Any) -> Any:
        parses.append(source)
        return parse(source, *args, **kwargs)

    def counted_walk(node: ast.AST) -> Any:
        for child in walk(node):
            walked[0] += 1
            yield child

    monkeypatch.setattr(ast, "parse", counted_parse)
    monkeypatch.setattr(ast, "walk", counted_walk)
    _, warnings = load_mission(path)
    monkeypatch.undo()
    lines = text.splitlines()
    assert [(w.line, w.col) for w in warnings if "time.sleep" in w.message] == [
        next((n, line.index(sleep) + 1) for n, line in enumerate(lines, 1) if sleep in line)
        for sleep in ("time.sleep(1)", "time.sleep(2)")
    ]
    # once as it is loaded (the rules read from its text), once for where things are in it
    assert sum(source in (text, text.encode()) for source in parses) == 2
    assert walked[0] < 8 * file_nodes, (walked[0], file_nodes)


def test_a_class_of_many_states_is_read_in_one_pass_for_where_each_was_written(
    tmp_path: Path,
) -> None:
    # where each of a mission's states was written was a pass over the whole class body
    # for each state: checking a mission took time in the square of its states
    from roboscript.mission.python_source import PythonSource

    path = tmp_path / "m.py"
    path.write_text("class M:\n" + "".join(f"    s{n} = {n}\n" for n in range(300)))
    source = PythonSource(str(path), "m.py")
    cls_node = source.class_def("M")
    assert cls_node is not None
    passes = [0]

    class Counted(list[Any]):
        def __iter__(self) -> Any:
            passes[0] += 1
            return super().__iter__()

    cls_node.body = Counted(cls_node.body)
    found = [source.assignment(cls_node, f"s{n}") for n in range(300)]
    assert [source.loc(item[1]).line if item else None for item in found] == list(range(2, 302))
    assert passes[0] == 1
