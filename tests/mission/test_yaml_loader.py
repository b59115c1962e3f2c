"""Golden messages for mistakes in mission files: file:line:col, what was meant, a hint."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from helpers import refusal as problems
from helpers import run_cli

from roboscript.errors import MissionError
from roboscript.inputs.source import YAML_1_1_WORDS
from roboscript.mission import load_mission, yaml_loader
from roboscript.mission.runner import MissionRunner
from roboscript.mission.spec import ActionSpec, MissionSpec, TransitionSpec
from roboscript.mission.yaml_loader import load_yaml_mission, parse_yaml_mission
from roboscript.profiles import get_profile

GOOD = """\
mission: ok
initial: go
states:
  go:
    do: {drive: {distance: 30 cm}}
    on: {done: end, failed: end}
  end:
    final: success
"""


def test_valid_mission_loads_with_units_converted(write_mission: Callable[..., Path]) -> None:
    spec, warnings = load_mission(write_mission(GOOD))
    assert spec.name == "ok" and spec.initial == "go"
    go = spec.states["go"].action
    assert dict(go.kwargs) == {"distance_mm": 300.0, "speed_mm_s": 150.0, "duration_s": None}
    assert spec.states["end"].final == "success"
    assert warnings == []


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (
            GOOD.replace("drive:", "drvie:"),
            "M:5:10: error: unknown action 'drvie' (did you mean 'drive'?)",
        ),
        (
            GOOD.replace("distance: 30 cm", "distnce: 30 cm"),
            "M:5:18: error: 'drive' has no parameter 'distnce' (did you mean 'distance'?)",
        ),
        (
            GOOD.replace("distance: 30 cm", "distance: 30 deg"),
            (
                "M:5:28: error: drive distance: 'deg' is a unit of angle, but this is a distance"
                " (use mm, cm, m, in)"
            ),
        ),
        (
            GOOD.replace("distance: 30 cm", "speed: 50 deg"),
            (
                "M:5:25: error: drive speed: 'deg' is a unit of angle, but this is a speed"
                " (use mm/s, cm/s, m/s, in/s, mm/sec)"
            ),
        ),
        (
            GOOD.replace("{done: end, failed: end}", "{done: ned, failed: end}"),
            "M:6:16: error: there is no state 'ned' (did you mean 'end'?)",
        ),
        (
            GOOD.replace("{done: end, failed: end}", "{dnoe: end, failed: end}"),
            (
                "M:6:10: error: unknown outcome 'dnoe' (outcomes: done, failed, timeout)"
                " (did you mean 'done'?)"
            ),
        ),
        (
            GOOD.replace("{done: end, failed: end}", "{finished: end, failed: end}"),
            (
                "M:6:10: error: unknown outcome 'finished' (outcomes: done, failed, timeout)"
                " (write done: end)"
            ),
        ),
        (
            GOOD.replace("initial: go", "initial: og"),
            "M:2:10: error: the initial state 'og' is not one of the states (did you mean 'go'?)",
        ),
        (
            GOOD.replace("    final: success", "    finale: success"),
            "M:8:5: error: unknown key 'finale' in state 'end' (did you mean 'final'?)",
        ),
        (
            GOOD + "  lost:\n    do: {wait: {duration: 1 s}}\n    on: {done: end}\n",
            (
                "M:9:3: error: state 'lost' can never be reached from 'go'"
                " (add a transition to it, or remove it)"
            ),
        ),
        (
            GOOD.replace("    on: {done: end, failed: end}\n", ""),
            (
                "M:4:3: error: state 'go' has no way out"
                " (add 'on: {done: NEXT}', a 'when' condition, or 'final: success')"
            ),
        ),
        (
            GOOD.replace("do: {drive: {distance: 30 cm}}", "do: {drive: {speed: 10 cm/s}}"),
            (
                "M:5:10: error: drive needs a distance or a duration"
                " (write `distance: 50 cm` or `duration: 2 s`)"
            ),
        ),
        (
            GOOD.replace("do: {drive: {distance: 30 cm}}", "do: {play_tone: {duration: 1 s}}"),
            "M:5:10: error: 'play_tone' needs 'frequency', pitch (write `frequency: 880 Hz`)",
        ),
        (
            GOOD.replace(
                "do: {drive: {distance: 30 cm}}", 'do: {wait_until: {condition: "bumper.any"}}'
            ),
            (
                "M:5:10: error: 'wait_until' needs 'timeout', the most it waits"
                " (every wait has a bound) (write `timeout: 10 s`)"
            ),
        ),
        (
            GOOD.replace("do: {drive: {distance: 30 cm}}", "do: {follow_wall: {side: left}}"),
            (
                "M:5:10: error: 'follow_wall' in state 'go' never ends as written (write"
                " `until: range.distance_cm < 20` or `duration: 10 s`, or give the state"
                " `timeout: 10 s` or a `when`)"
            ),
        ),
        (
            GOOD.replace(
                "do: {drive: {distance: 30 cm}}",
                'do: {wait_until: {condition: "rnage.distance_cm < 3", timeout: 2 s}}',
            ),
            (
                "M:5:35: error: wait_until condition: unknown name 'rnage' in a condition"
                " (did you mean 'range'?)"
            ),
        ),
        (
            GOOD.replace("do: {drive: {distance: 30 cm}}", "do: {set_led: {color: mauve}}"),
            (
                "M:5:27: error: set_led color: expected a colour (off, black, white, red, green,"
                " blue, yellow, orange, purple, cyan, pink, '#RRGGBB' or [r, g, b]), got 'mauve'"
            ),
        ),
        (
            "mission: x\nstates: []\n",
            (
                "M:2:1: error: a mission needs 'states:', a mapping of state names to states"
                " (under states:, indented, write each state by its name, e.g. go: {final:"
                " success})"
            ),
        ),
        (
            "states:\n  a:\n    final: success\n  a:\n    final: failure\n",
            (
                "M:4:3: error: 'a' is given twice (first on line 2) (keep one of the two, or give"
                " one of them another name)"
            ),
        ),
        (
            "states:\n  a: {final: success\n",
            "M:2:6: error: this `{` is never closed (close it with `}`)",
        ),
    ],
)
def test_golden_errors(write_mission: Callable[..., Path], text: str, expected: str) -> None:
    assert problems(write_mission(text))[0] == expected


def test_guard_errors_point_into_the_condition(write_mission: Callable[..., Path]) -> None:
    text = GOOD.replace(
        "    on: {done: end, failed: end}",
        "    on: {done: end, failed: end}\n    when:\n"
        '      - {if: "range.distnce_cm < 20", goto: end}',
    )
    assert problems(write_mission(text)) == [
        (
            "M:8:21: error: 'range' has no 'distnce_cm' (it has distance_cm, distance_mm)"
            " (did you mean 'range.distance_cm'?)"
        )
    ]


def test_yaml_tags_that_would_run_code_are_refused(write_mission: Callable[..., Path]) -> None:
    text = "mission: !!python/object/apply:os.system ['touch /tmp/roboscript-pwned']\nstates: {}\n"
    found = problems(write_mission(text))
    assert "is not allowed" in found[0]
    assert not Path("/tmp/roboscript-pwned").exists()


def test_unhandled_outcomes_are_warnings(write_mission: Callable[..., Path]) -> None:
    text = GOOD.replace("{done: end, failed: end}", "{done: end}").replace(
        "    on: {done: end}", "    timeout: 5 s\n    on: {done: end}"
    )
    _spec, warnings = load_mission(write_mission(text))
    assert [w.format().split(": warning: ")[1] for w in warnings] == [
        (
            "if state 'go' times out the mission ends in failure"
            " (add 'on: {timeout: STATE}' to handle it)"
        ),
        (
            "if 'drive' fails (stalled) in state 'go', the mission ends in failure"
            " (add 'on: {failed: STATE}' to handle it)"
        ),
    ]


def test_follow_line_on_a_robot_without_line_sensors_is_refused(
    write_mission: Callable[..., Path],
) -> None:
    from dataclasses import replace

    no_line = replace(
        get_profile("mirto"), name="wheels-only", capabilities=frozenset({"drive_base"})
    )
    text = GOOD.replace("do: {drive: {distance: 30 cm}}", "do: {follow_line: {duration: 5 s}}")
    assert problems(write_mission(text), no_line) == [
        (
            "M:5:10: error: 'follow_line' needs line (downward IR line sensors),"
            " which wheels-only does not have (use follow_wall or drive with a range condition)"
        )
    ]


def test_a_during_action_the_robot_cannot_serve_is_refused_at_load_time(
    write_mission: Callable[..., Path],
) -> None:
    from dataclasses import replace

    no_speaker = replace(get_profile("mirto"), name="quiet", capabilities=frozenset({"drive_base"}))
    text = GOOD.replace(
        "    on: {done: end, failed: end}",
        "    during: [{play_tone: {frequency: 440 Hz, duration: 1 s}}]\n"
        "    on: {done: end, failed: end}",
    )
    assert problems(write_mission(text), no_speaker) == [
        ("M:6:15: error: 'play_tone' needs speaker (a tone generator), which quiet does not have")
    ]


def test_robot_without_a_capability_is_named(write_mission: Callable[..., Path]) -> None:
    from dataclasses import replace

    no_line = replace(get_profile("mirto"), name="bare", capabilities=frozenset({"drive_base"}))
    text = GOOD.replace(
        "    on: {done: end, failed: end}",
        '    on: {done: end, failed: end}\n    when:\n      - {if: "line.center > 600", goto: end}',
    )
    assert problems(write_mission(text), no_line) == [
        (
            "M:8:9: error: the condition 'line.center > 600' reads line, which bare does not have"
            " (use follow_wall or drive with a range condition)"
        )
    ]


def test_file_that_is_not_yaml_mission(tmp_path: Path) -> None:
    path = tmp_path / "m.txt"
    path.write_text("x", encoding="utf-8")
    with pytest.raises(MissionError, match=r"ends in \.yaml"):
        load_mission(path)


def test_missing_file_is_a_mission_error(tmp_path: Path) -> None:
    with pytest.raises(MissionError, match="cannot read the file"):
        load_mission(tmp_path / "none.yaml")


def test_a_condition_error_has_the_same_column_from_text_as_from_a_file(
    write_mission: Callable[..., Path],
) -> None:
    from roboscript.mission.yaml_loader import parse_yaml_mission

    text = GOOD.replace(
        "    on: {done: end, failed: end}",
        '    on: {done: end, failed: end}\n    when: [{if: "range.distance_cm < = 20", goto: end}]',
    )
    with pytest.raises(MissionError) as from_text:
        parse_yaml_mission(text, "typed-in.yaml")  # no such file: the text is all there is
    with pytest.raises(MissionError) as from_file:
        load_mission(write_mission(text))
    # col 17 is the opening quote; the second '=' the compiler stumbles on is col 38.
    for error in (from_text.value, from_file.value):
        assert ":7:38: error: cannot read the condition" in str(error)


# ----------------------------------------------------------- where a state's parts belong


def test_an_action_written_under_the_state_says_it_goes_under_do(
    write_mission: Callable[..., Path],
) -> None:
    text = GOOD.replace("do: {drive: {distance: 30 cm}}", "drive: {distance: 30 cm}")
    assert problems(write_mission(text))[0] == (
        "M:5:5: error: 'drive' is an action, and a state runs its action under 'do:'"
        " (write do: {drive: {...}})"
    )


def test_a_key_that_is_no_action_keeps_its_did_you_mean(
    write_mission: Callable[..., Path],
) -> None:
    text = GOOD.replace("on: {done: end", "onn: {done: end")
    assert problems(write_mission(text))[0] == (
        "M:6:5: error: unknown key 'onn' in state 'go' (did you mean 'on'?)"
    )


def test_an_on_indented_as_far_as_the_states_names_the_state_it_belongs_to(
    write_mission: Callable[..., Path],
) -> None:
    text = GOOD.replace("    on: {done: end", "  on: {done: end")
    assert problems(write_mission(text)) == [
        (
            "M:6:3: error: 'on:' is indented as far as the state names, so it makes a state called"
            " 'on' (indent it two more spaces, under 'go:', to make it part of state 'go')"
        )
    ]


def test_a_dedented_timeout_is_told_the_same_way(write_mission: Callable[..., Path]) -> None:
    text = GOOD.replace("  end:\n", "  timeout: 5 s\n  end:\n")
    assert problems(write_mission(text))[0].startswith(
        "M:7:3: error: 'timeout:' is indented as far as the state names"
    )


def test_a_state_called_final_with_a_states_keys_is_a_state(
    write_mission: Callable[..., Path],
) -> None:
    text = GOOD.replace("on: {done: end, failed: end}", "on: {done: final, failed: final}")
    text = text.replace("  end:\n    final: success\n", "  final:\n    final: success\n")
    spec, _ = load_mission(write_mission(text))
    assert spec.states["final"].final == "success"


# -------- Every message for a YAML mistake, and the whole spec a sound mission builds
#
# YAML missions: every message a student reads for a mistake, whole, and the whole spec a
# sound mission builds, nested parts included.
#
# Each case writes the mission (and any file it uses) to ``tmp_path`` and compares every
# problem the loader collects, with its ``file:line:col`` and hint, so a message, a position or
# a hint that changes, or a problem that goes missing or is reported twice, fails here. The
# spec is compared as an outline that includes what ``ActionSpec`` leaves out of ``==`` (the
# children of ``parallel``/``repeat``, inner machines, where each parameter was written).


def write(tmp_path: Path, files: dict[str, str]) -> Path:
    """Write the files; the first is the mission to load."""
    for name, text in files.items():
        (tmp_path / name).write_text(text, encoding="utf-8")
    return tmp_path / next(iter(files))


def report(path: Path) -> list[str]:
    """Every problem a student reads, with the folder left out; ``OK`` then the warnings for a
    mission that loads."""
    try:
        _, warnings = load_yaml_mission(path)
    except MissionError as exc:
        found = getattr(exc, "problems", [exc])
        # `roboscript check` and the grader catch MissionError, whichever problem comes first
        assert all(isinstance(p, MissionError) for p in found)
        return [p.format().replace(f"{path.parent}/", "") for p in found]
    return ["OK"] + [w.format().replace(f"{path.parent}/", "") for w in warnings]


def _where(location: Any) -> str:
    return str(location).rsplit("/", 1)[-1]


def _action(spec: ActionSpec, indent: str) -> list[str]:
    kwargs = " ".join(f"{k}={getattr(v, 'source', v)!r}" for k, v in spec.kwargs.items())
    params = " ".join(f"{k}@{_where(v)}" for k, v in spec.param_locations.items())
    lines = [
        (
            f"{indent}{spec.name} @{_where(spec.location)} bounded={spec.bounded}"
            f" requires={','.join(sorted(spec.requires))}"
        ),
        f"{indent}  with {kwargs}",
    ]
    if params:
        lines.append(f"{indent}  params at {params}")
    for child in spec.children:
        lines += _action(child, indent + "  ")
    if spec.inner is not None:
        lines += _mission(spec.inner, indent + "  ")
    return lines


def _transition(t: TransitionSpec) -> str:
    guard = "" if t.guard is None else f" if {t.guard_text!r}"
    assert (t.guard is None) == (t.guard_text is None)  # a guard always shows as written
    return f"{t.target}{guard} @{_where(t.location)}"


def _mission(spec: MissionSpec, indent: str = "") -> list[str]:
    lines = [
        (
            f"{indent}mission {spec.name!r} initial={spec.initial} @{_where(spec.location)}"
            f" path={_where(spec.path)} description={spec.description!r}"
        ),
        (
            f"{indent}robot={spec.robot} @{_where(spec.robot_location)}"
            f" world={spec.world} @{_where(spec.world_location)}"
        ),
    ]
    for state in spec.states.values():
        lines.append(
            f"{indent}- {state.name} @{_where(state.location)} timeout={state.timeout_s}"
            f" final={state.final} description={state.description!r}"
        )
        if state.action is not None:
            lines += _action(state.action, indent + "  do: ")
        for extra in state.during:
            lines += _action(extra, indent + "  during: ")
        for outcome, transitions in state.on.items():
            lines.append(f"{indent}  on {outcome}: " + ", ".join(map(_transition, transitions)))
        if state.when:
            lines.append(f"{indent}  when: " + ", ".join(map(_transition, state.when)))
    return lines


def outline(spec: MissionSpec) -> str:
    return "\n".join(_mission(spec))


TOGETHER_HINT = (
    "(write `parallel: {all: [{drive: {distance: 50 cm}}, {play_tone: {frequency: 880 Hz}}]}`;"
    " with any: it ends when the first one does)"
)
TOGETHER = f"actions to run together {TOGETHER_HINT}"
AGAIN = "(write `repeat: {times: 4, do: {rotate: {angle: 90 deg}}}`)"

MISTAKES = [
    pytest.param(
        {
            "m.yaml": ("- go\n"),
        },
        [
            (
                "m.yaml:1:1: error: a mission file is a mapping with 'mission:', 'initial:'"
                " and 'states:' (this file holds a list; a mission starts `mission: NAME`, then"
                " `states:` with each state indented under it)"
            ),
        ],
        id="not_a_mapping",
    ),
    pytest.param(
        {"m.yaml": "drive 30 cm then turn\n"},
        [
            (
                "m.yaml:1:1: error: a mission file is a mapping with 'mission:', 'initial:'"
                " and 'states:' (this file holds plain text; a mission starts `mission: NAME`,"
                " then `states:` with each state indented under it)"
            ),
        ],
        id="plain_text",
    ),
    pytest.param(
        {
            "m.yaml": ("mision: x\ninitial: go\nstates: {go: {final: success}}\n"),
        },
        [
            "m.yaml:1:1: error: unknown key 'mision' in a mission (did you mean 'mission'?)",
        ],
        id="misspelt_top_key",
    ),
    pytest.param(
        {
            "m.yaml": ("# a mission\nmission: x\nstatse: 3\n"),
        },
        [
            (
                "m.yaml:2:1: error: a mission needs 'states:', a mapping of state names to states"
                " (write states: and under it, indented, each state, e.g. go: {final: success})"
            ),
            "m.yaml:3:1: error: unknown key 'statse' in a mission (did you mean 'states'?)",
        ],
        id="no_states_after_comment",
    ),
    pytest.param(
        {
            "m.yaml": ("robot: [a]\nworld: 3\nstates:\n  s: 5\n  e:\n    final: sucess\n"),
        },
        [
            "m.yaml:1:8: error: 'robot' names a robot, e.g. robot: mirto",
            "m.yaml:2:8: error: 'world' names a world, e.g. world: square-room",
            "m.yaml:4:6: error: state 's' must be a mapping (do:, on:, when:, final:)",
            (
                "m.yaml:6:12: error: state 'e': final is 'success' or 'failure', got 'sucess'"
                " (did you mean 'success'?)"
            ),
        ],
        id="robot_world_not_names",
    ),
    pytest.param(
        {
            "m.yaml": (
                "behaviours: moves.py\n"
                "states:\n"
                "  go:\n"
                "    do: spin\n"
                "    on: {done: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            "m.yaml:1:13: error: there is no behaviour file 'moves.py' beside the mission",
            "m.yaml:4:9: error: unknown action 'spin' (did you mean 'stop'?)",
        ],
        id="behaviours_file_missing",
    ),
    pytest.param(
        {
            "m.yaml": ("states:\n  go:\n  end:\n    final: success\n"),
        },
        [
            (
                "m.yaml:2:3: error: state 'go' has no way out (add 'on: {done: NEXT}', a"
                " 'when' condition, or 'final: success')"
            ),
            (
                "m.yaml:3:3: error: state 'end' can never be reached from 'go' (add a"
                " transition to it, or remove it)"
            ),
        ],
        id="empty_state",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {wait_until: {condition: visits.og > 1, timeout: 2 s}}\n"
                "    on: {done: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            "m.yaml:3:41: error: wait_until condition: 'visits.og': there is no state 'og'",
        ],
        id="visits_typo_in_do",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {drive: {distance: 30 cm}}\n"
                "    during: {beep: {}}\n"
                "    on: {done: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            "m.yaml:4:13: error: 'during' is a list of actions run alongside 'do'",
        ],
        id="during_not_a_list",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {drive: {distance: 30 cm}}\n"
                "    during:\n"
                "      - {wait_until: {condition: visits.og > 1, timeout: 2 s}}\n"
                "      - {dirve: {}}\n"
                "      - {intial: a, states: {a: {final: success}}}\n"
                "    on: {done: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            "m.yaml:5:41: error: wait_until condition: 'visits.og': there is no state 'og'",
            "m.yaml:6:10: error: unknown action 'dirve' (did you mean 'drive'?)",
            (
                "m.yaml:7:10: error: unknown key 'intial' in the inner states of 'go' (did"
                " you mean 'initial'?)"
            ),
        ],
        id="during_items",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {drive: {distance: 30 cm}}\n"
                "    on: end\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            (
                "m.yaml:4:9: error: 'on' maps outcomes to states, e.g. on: {done: next,"
                " timeout: stuck} (write on: {done: end})"
            ),
        ],
        id="on_not_a_mapping",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {drive: {distance: 30 cm}}\n"
                "    when: {if: done, goto: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            (
                "m.yaml:4:11: error: 'when' is a list of choices, each a condition and the state"
                " it goes to (write `when: [{if: done, goto: end}]`, one {...} per choice)"
            ),
        ],
        id="when_not_a_list",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {drive: {distance: 30 cm}}\n"
                "    timeout: 5 cm\n"
                "    on: {done: end, timeout: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            (
                "m.yaml:4:14: error: state 'go': timeout: 'cm' is a unit of distance, but"
                " this is a time (use s, sec, ms, min)"
            ),
        ],
        id="timeout_wrong_unit",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {drive: {distance: 30 cm}}\n"
                "    timeout: 5\n"
                "    on: {done: end, timeout: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            "OK",
            "m.yaml:4:14: warning: state 'go': timeout: 5 taken as 5 s; write `5 s`",
            (
                "m.yaml:3:10: warning: if 'drive' fails (stalled) in state 'go', the mission"
                " ends in failure (add 'on: {failed: STATE}' to handle it)"
            ),
        ],
        id="timeout_bare_number",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {drive: {distance: 30 cm}}\n"
                "    timeout: 500\n"
                "    on: {done: end, failed: end, timeout: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            "OK",
            (
                "m.yaml:4:14: warning: state 'go': timeout: 500 taken as 500 s; write `500"
                " s` (or did you mean 500 ms?)"
            ),
        ],
        id="timeout_bare_number_likely_ms",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {drive: {distance: 30 cm}}\n"
                "    timeout: -2 s\n"
                "    on: {done: end, timeout: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            (
                "m.yaml:4:14: error: state 'go': timeout is a positive number of seconds,"
                " got '-2 s' (write `timeout: 10 s`)"
            ),
        ],
        id="timeout_negative",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n  go:\n    do: [drive]\n    on: {done: end}\n  end:\n    final: success\n"
            ),
        },
        [
            (
                "m.yaml:3:9: error: 'do' names one action, e.g. do: {drive: {distance: 50 cm}}"
                " (to do one thing after another, give each its own state and go on with"
                " on: {done: NEXT})"
            ),
        ],
        id="do_a_list",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n  go:\n    do: 5\n    on: {done: end}\n  end:\n    final: success\n"
            ),
        },
        [
            "m.yaml:3:9: error: 'do' names one action, e.g. do: {drive: {distance: 50 cm}}",
        ],
        id="do_a_number",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {drive: {distance: 3 cm}, turn: {angle: 90 deg}}\n"
                "    on: {done: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            (
                "m.yaml:3:9: error: 'do' names one action, e.g. do: {drive: {distance: 50 cm}}"
                " (to do one thing after another, give each its own state and go on with"
                " on: {done: NEXT}; to do them at once, use parallel:)"
            ),
        ],
        id="do_two_actions",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {drive: 30 cm}\n"
                "    on: {done: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            (
                "m.yaml:3:17: error: the parameters of 'drive' must be a mapping, each with its"
                " name (write `{drive: {distance: 30 cm}}`)"
            ),
        ],
        id="params_not_a_mapping",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do:\n"
                "      turn:\n"
                "    on: {done: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            (
                "m.yaml:4:7: error: 'turn' needs 'steps', how many turning steps"
                " (positive = right) (write `steps: 4`)"
            ),
        ],
        id="params_empty",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n  go:\n    do: turn\n    on: {done: end}\n  end:\n    final: success\n"
            ),
        },
        [
            (
                "m.yaml:3:9: error: 'turn' needs 'steps', how many turning steps"
                " (positive = right) (write `steps: 4`)"
            ),
        ],
        id="bare_action_missing_param",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  a:\n"
                "    do: {parallel: [stop]}\n"
                "    on: {done: b}\n"
                "  b:\n"
                "    do: {parallel: {all: [stop], any: [stop]}}\n"
                "    on: {done: c}\n"
                "  c:\n"
                "    do: {parallel: {some: [stop]}}\n"
                "    on: {done: d}\n"
                "  d:\n"
                "    do: {parallel: {any: [stop]}}\n"
                "    on: {done: e}\n"
                "  e:\n"
                "    do: {parallel: {all: []}}\n"
                "    on: {done: f}\n"
                "  f:\n"
                "    do: {parallel: {any: stop}}\n"
                "    on: {done: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            f"m.yaml:3:10: error: parallel needs 'all' or 'any', with the list of {TOGETHER}",
            f"m.yaml:6:10: error: parallel takes 'all' or 'any', not both {TOGETHER_HINT}",
            f"m.yaml:9:10: error: parallel needs 'all' or 'any', with the list of {TOGETHER}",
            f"m.yaml:15:26: error: parallel all: needs a list of actions {TOGETHER_HINT}",
            f"m.yaml:18:26: error: parallel any: needs a list of actions {TOGETHER_HINT}",
        ],
        id="parallel_wrong",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do:\n"
                "      parallel:\n"
                "        all:\n"
                "          - {drive: {distance: 30 cm}}\n"
                "          - {wait_until: {condition: visits.og > 1, timeout: 2 s}}\n"
                "          - {dirve: {}}\n"
                "    on: {done: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            "m.yaml:7:45: error: wait_until condition: 'visits.og': there is no state 'og'",
            "m.yaml:8:14: error: unknown action 'dirve' (did you mean 'drive'?)",
        ],
        id="parallel_bad_children",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  a:\n"
                "    do: {repeat: {times: 2}}\n"
                "    on: {done: b}\n"
                "  b:\n"
                "    do: {repeat: [stop]}\n"
                "    on: {done: c}\n"
                "  c:\n"
                "    do: {repeat: {times: 0, do: stop}}\n"
                "    on: {done: d}\n"
                "  d:\n"
                "    do: {repeat: {times: true, do: stop}}\n"
                "    on: {done: e}\n"
                "  e:\n"
                "    do: {repeat: {times: 1.5, do: stop}}\n"
                "    on: {done: f}\n"
                "  f:\n"
                "    do: {repeat: {times: 2, do: {dirve: {}}}}\n"
                "    on: {done: g}\n"
                "  g:\n"
                "    do:\n"
                "      repeat:\n"
                "        times: 3\n"
                "        do: {wait_until: {condition: visits.og > 1, timeout: 2 s}}\n"
                "    on: {done: h}\n"
                "  h:\n"
                "    do: {repeat: {times: 2, do: 5}}\n"
                "    on: {done: i}\n"
                "  i:\n"
                "    do: {repeat: {times: 2, do: {intial: a, states: {a: {final: success}}}}}\n"
                "    on: {done: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            f"m.yaml:3:10: error: repeat needs 'do', the action to repeat {AGAIN}",
            (
                "m.yaml:6:10: error: repeat needs 'times', how many times, and 'do', the action"
                f" to repeat {AGAIN}"
            ),
            (
                "m.yaml:9:26: error: repeat times: 0 would not run the action at all (at least 1)"
                f" {AGAIN}"
            ),
            (
                "m.yaml:12:26: error: repeat needs 'times', a whole number of at least 1, and"
                f" true is not a number {AGAIN}"
            ),
            (
                "m.yaml:15:26: error: repeat times is a whole number of runs, and 1.5 is not one"
                f" {AGAIN}"
            ),
            "m.yaml:18:34: error: unknown action 'dirve' (did you mean 'drive'?)",
            (
                "m.yaml:24:45: error: wait_until condition: 'visits.og': there is no state"
                " 'og' (did you mean 'visits.g'?)"
            ),
            "m.yaml:27:33: error: 'do' names one action, e.g. do: {drive: {distance: 50 cm}}",
            (
                "m.yaml:30:34: error: unknown key 'intial' in the inner states of 'i' (did"
                " you mean 'initial'?)"
            ),
        ],
        id="repeat_wrong",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do:\n"
                "      intial: a\n"
                "      states:\n"
                "        a:\n"
                "          do: {drvie: {}}\n"
                "          on: {done: b}\n"
                "        b:\n"
                "          final: success\n"
                "    on: {done: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            (
                "m.yaml:4:7: error: unknown key 'intial' in the inner states of 'go' (did"
                " you mean 'initial'?)"
            ),
            "m.yaml:7:16: error: unknown action 'drvie' (did you mean 'drive'?)",
        ],
        id="inner_machine_mistakes",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do:\n"
                "      states:\n"
                "        a:\n"
                "          do: {drive: {distance: 3 cm}}\n"
                "          on: {done: a}\n"
                "    on: {done: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            (
                "m.yaml:5:9: error: mission 'go' can never finish: no final state can be"
                " reached from 'a' (add a state with 'final: success' and a transition to"
                " it, e.g. on: {done: finished})"
            ),
            (
                "m.yaml:6:16: warning: if 'drive' fails (stalled) in state 'a', the mission"
                " ends in failure (add 'on: {failed: STATE}' to handle it)"
            ),
        ],
        id="inner_machine_no_ending",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {mission: [a.yaml]}\n"
                "    on: {done: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            "m.yaml:3:19: error: mission: names a mission file, e.g. mission: patrol.yaml",
        ],
        id="mission_not_a_name",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {mission: patorl.yaml}\n"
                "    on: {done: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
            "patrol.yaml": ("states:\n  p:\n    final: success\n"),
        },
        [
            (
                "m.yaml:3:19: error: there is no mission file 'patorl.yaml' beside the"
                " mission (did you mean 'patrol.yaml'?)"
            ),
        ],
        id="mission_file_missing",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {mission: bad.yaml}\n"
                "    on: {done: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
            "bad.yaml": ("states: [\n"),
        },
        [
            (
                "bad.yaml:2:1: error: the file ends where a value was expected (close each `[` and"
                " `{` it opens)"
            ),
        ],
        id="mission_file_not_yaml",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {mission: patorl.yml}\n"
                "    on: {done: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
            "patrol.yml": ("states:\n  p:\n    final: success\n"),
        },
        [
            (
                "m.yaml:3:19: error: there is no mission file 'patorl.yml' beside the"
                " mission (did you mean 'patrol.yml'?)"
            ),
        ],
        id="mission_file_yml_misspelt",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {mission: bad.yaml}\n"
                "    on: {done: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
            "bad.yaml": (
                "states:\n  p:\n    do: {dirve: {}}\n    on: {done: q}\n  q:\n    final: sucess\n"
            ),
        },
        [
            "bad.yaml:3:10: error: unknown action 'dirve' (did you mean 'drive'?)",
            (
                "bad.yaml:6:12: error: state 'q': final is 'success' or 'failure', got 'sucess'"
                " (did you mean 'success'?)"
            ),
        ],
        id="mission_file_with_two_errors",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {mission: m.yaml}\n"
                "    on: {done: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            "m.yaml:3:19: error: 'm.yaml' includes itself (directly or through another file)",
        ],
        id="mission_includes_itself",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {mission: bad.yaml}\n"
                "    on: {done: two}\n"
                "  two:\n"
                "    do: {mission: bad.yaml}\n"
                "    on: {done: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
            "bad.yaml": (
                "states:\n  p:\n    do: {dirve: {}}\n    on: {done: q}\n  q:\n    final: success\n"
            ),
        },
        [
            "bad.yaml:3:10: error: unknown action 'dirve' (did you mean 'drive'?)",
        ],
        id="mission_file_with_errors_used_twice",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {mission: warn.yml}\n"
                "    on: {done: two}\n"
                "  two:\n"
                "    do: {mission: warn.yml}\n"
                "    on: {done: end}\n"
                "  end:\n"
                "    do: {drive: {distance: 30 cm}}\n"
                "    timeout: 3\n"
                "    on: {done: fin, timeout: fin}\n"
                "  fin:\n"
                "    final: failure\n"
            ),
            "warn.yml": (
                "states:\n"
                "  p:\n"
                "    do: {drive: {distance: 3 cm}}\n"
                "    timeout: 4\n"
                "    on: {done: q, timeout: q}\n"
                "  q:\n"
                "    final: success\n"
            ),
        },
        [
            "OK",
            "warn.yml:4:14: warning: state 'p': timeout: 4 taken as 4 s; write `4 s`",
            (
                "warn.yml:3:10: warning: if 'drive' fails (stalled) in state 'p', the"
                " mission ends in failure (add 'on: {failed: STATE}' to handle it)"
            ),
            "m.yaml:10:14: warning: state 'end': timeout: 3 taken as 3 s; write `3 s`",
            (
                "m.yaml:9:10: warning: if 'drive' fails (stalled) in state 'end', the"
                " mission ends in failure (add 'on: {failed: STATE}' to handle it)"
            ),
        ],
        id="mission_file_with_warning_used_twice",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {drive: {distance: 30 cm}}\n"
                '    on: {dnoe: end, faild: end, done: [ned, {if: "distance < 5", goto:'
                " end}, 7, {goto: go, iff: x}, {if: bump}], timeout: end}\n"
                "    timeout: 2 s\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            (
                "m.yaml:4:10: error: unknown outcome 'dnoe' (outcomes: done, failed,"
                " timeout) (did you mean 'done'?)"
            ),
            (
                "m.yaml:4:21: error: unknown outcome 'faild' (outcomes: done, failed,"
                " timeout) (did you mean 'failed'?)"
            ),
            "m.yaml:4:40: error: there is no state 'ned' (did you mean 'end'?)",
            (
                "m.yaml:4:51: error: unknown name 'distance' in a condition: a sensor's value is"
                " named with its sensor and its unit (write 'range.distance_cm' or"
                " 'side_range.distance_cm')"
            ),
            (
                "m.yaml:4:78: error: a choice is a condition and the state it goes to"
                " (write `{if: range.distance_cm < 20, goto: end}`)"
            ),
            "m.yaml:4:92: error: unknown key 'iff' in a choice (did you mean 'if'?)",
            (
                "m.yaml:4:101: error: this choice needs 'goto', the state it goes to"
                " (write `goto: end`)"
            ),
        ],
        id="on_mistakes",
    ),
    pytest.param(
        {
            "m.yaml": (
                "states:\n"
                "  go:\n"
                "    do: {drive: {distance: 30 cm}}\n"
                '    when: [end, {goto: end}, {if: "visits.og > 1", goto: end}, {if:'
                ' "distance <", goto: end}, {if: bump, goto: ned}]\n'
                "    on: {done: end}\n"
                "  end:\n"
                "    final: success\n"
            ),
        },
        [
            (
                "m.yaml:4:12: error: a choice is a condition and the state it goes to"
                " (write `{if: range.distance_cm < 20, goto: end}`)"
            ),
            (
                "m.yaml:4:17: error: each 'when' entry needs 'if', the condition that moves on"
                " (write `if: range.distance_cm < 20`)"
            ),
            "m.yaml:4:43: error: 'visits.og': there is no state 'og'",
            "m.yaml:4:70: error: cannot read the condition 'distance <'",
            "m.yaml:4:100: error: unknown name 'bump' in a condition (did you mean 'bumper'?)",
            "m.yaml:4:112: error: there is no state 'ned' (did you mean 'end'?)",
        ],
        id="when_mistakes",
    ),
]


@pytest.mark.parametrize(("files", "expected"), MISTAKES)
def test_every_problem_in_a_mission_file(
    tmp_path: Path, files: dict[str, str], expected: list[str]
) -> None:
    assert report(write(tmp_path, files)) == expected


PATROL = """\
states:
  look:
    do: {wait: {duration: 1 s}}
    on: {done: back}
  back:
    final: success
"""

TOUR = """\
mission: tour
description: Round the room.
robot: mirto
world: square-room
states:
  go:
    description: Off we go.
    do: {drive: {distance: 30 cm}}
    during:
      - stop
      - {play_tone: {frequency: 440 Hz, duration: 0.2 s}}
    timeout: 8 s
    on:
      done: [{if: " visits.go > 2", goto: end}, {goto: both}]
      failed: end
      timeout: end
    when:
      - {if: bumper.left, goto: end}
      - {if: true, goto: both}
  both:
    do:
      parallel:
        any:
          - {drive: {distance: 20 cm}}
          - {wait_until: {condition: visits.both > 1, timeout: 2 s}}
    on: {done: loop, failed: end}
  loop:
    do:
      repeat:
        times: 1
        do: {wait_until: {condition: visits.loop > 1, timeout: 2 s}}
    on: {done: inner, failed: end}
  inner:
    do:
      initial: b
      states:
        a:
          final: success
        b:
          do:
            parallel:
              all: [stop, {states: {c: {final: failure}}}]
          on: {done: a}
    on: {done: patrol, failed: end}
  patrol:
    do: {mission: patrol.yaml}
    on: {done: end, failed: end}
  end:
    final: true
"""


TOUR_OUTLINE = """\
mission 'tour' initial=go @m.yaml:1:1 path=m.yaml description='Round the room.'
robot=mirto @m.yaml:3:8 world=square-room @m.yaml:4:8
- go @m.yaml:6:3 timeout=8.0 final=None description='Off we go.'
  do: drive @m.yaml:8:10 bounded=True requires=drive_base
  do:   with distance_mm=300.0 speed_mm_s=150.0 duration_s=None
  do:   params at distance@m.yaml:8:28
  during: stop @m.yaml:10:9 bounded=True requires=drive_base
  during:   with 
  during: play_tone @m.yaml:11:10 bounded=True requires=speaker
  during:   with frequency_hz=440.0 duration_s=0.2
  during:   params at frequency@m.yaml:11:33 duration@m.yaml:11:51
  on done: end if ' visits.go > 2' @m.yaml:14:14, both @m.yaml:14:49
  on failed: end @m.yaml:15:15
  on timeout: end @m.yaml:16:16
  when: end if 'bumper.left' @m.yaml:18:9, both if 'true' @m.yaml:19:9
- both @m.yaml:20:3 timeout=None final=None description=''
  do: parallel @m.yaml:22:7 bounded=True requires=drive_base
  do:   with mode='any' actions=('drive', 'wait_until')
  do:   drive @m.yaml:24:14 bounded=True requires=drive_base
  do:     with distance_mm=200.0 speed_mm_s=150.0 duration_s=None
  do:     params at distance@m.yaml:24:32
  do:   wait_until @m.yaml:25:14 bounded=True requires=
  do:     with condition='visits.both > 1' timeout_s=2.0
  do:     params at condition@m.yaml:25:38 timeout@m.yaml:25:64
  on done: loop @m.yaml:26:16
  on failed: end @m.yaml:26:30
- loop @m.yaml:27:3 timeout=None final=None description=''
  do: repeat @m.yaml:29:7 bounded=True requires=
  do:   with times=1 action='wait_until'
  do:   wait_until @m.yaml:31:14 bounded=True requires=
  do:     with condition='visits.loop > 1' timeout_s=2.0
  do:     params at condition@m.yaml:31:38 timeout@m.yaml:31:64
  on done: inner @m.yaml:32:16
  on failed: end @m.yaml:32:31
- inner @m.yaml:33:3 timeout=None final=None description=''
  do: states @m.yaml:35:7 bounded=True requires=drive_base
  do:   with mission='inner' states=('a', 'b')
  do:   mission 'inner' initial=b @m.yaml:35:7 path=m.yaml description=''
  do:   robot=None @None world=None @None
  do:   - a @m.yaml:37:9 timeout=None final=success description=''
  do:   - b @m.yaml:39:9 timeout=None final=None description=''
  do:     do: parallel @m.yaml:41:13 bounded=True requires=drive_base
  do:     do:   with mode='all' actions=('stop', 'states')
  do:     do:   stop @m.yaml:42:21 bounded=True requires=drive_base
  do:     do:     with 
  do:     do:   states @m.yaml:42:27 bounded=True requires=
  do:     do:     with mission='b' states=('c',)
  do:     do:     mission 'b' initial=c @m.yaml:42:27 path=m.yaml description=''
  do:     do:     robot=None @None world=None @None
  do:     do:     - c @m.yaml:42:37 timeout=None final=failure description=''
  do:     on done: a @m.yaml:43:22
  on done: patrol @m.yaml:44:16
  on failed: end @m.yaml:44:32
- patrol @m.yaml:45:3 timeout=None final=None description=''
  do: states @m.yaml:46:19 bounded=True requires=
  do:   with mission='patrol' states=('look', 'back')
  do:   mission 'patrol' initial=look @patrol.yaml:1:1 path=patrol.yaml description=''
  do:   robot=None @None world=None @None
  do:   - look @patrol.yaml:2:3 timeout=None final=None description=''
  do:     do: wait @patrol.yaml:3:10 bounded=True requires=
  do:     do:   with duration_s=1.0
  do:     do:   params at duration@patrol.yaml:3:27
  do:     on done: back @patrol.yaml:4:16
  do:   - back @patrol.yaml:5:3 timeout=None final=success description=''
  on done: end @m.yaml:47:16
  on failed: end @m.yaml:47:29
- end @m.yaml:48:3 timeout=None final=success description=''
"""


def test_a_sound_mission_builds_every_part_where_it_was_written(tmp_path: Path) -> None:
    path = write(tmp_path, {"m.yaml": TOUR, "patrol.yaml": PATROL})
    spec, warnings = load_yaml_mission(path)
    assert outline(spec) + "\n" == TOUR_OUTLINE
    assert [w.format().replace(f"{tmp_path}/", "") for w in warnings] == [
        (
            "m.yaml:41:13: warning: if 'parallel' fails (its inner states reach a failure) in"
            " state 'b', the mission ends in failure (add 'on: {failed: STATE}' to handle it)"
        ),
        (
            "m.yaml:22:7: warning: if 'parallel' times out in state 'both', the mission ends in"
            " failure (add 'on: {timeout: STATE}' to handle it)"
        ),
        (
            "m.yaml:29:7: warning: if 'repeat' times out in state 'loop', the mission ends in"
            " failure (add 'on: {timeout: STATE}' to handle it)"
        ),
    ]


def test_a_mission_without_a_name_or_initial_takes_its_file_name_and_first_state(
    tmp_path: Path,
) -> None:
    path = write(tmp_path, {"square_dance.yaml": "states:\n  go:\n    final: success\n"})
    spec, warnings = load_yaml_mission(path)
    assert outline(spec) == (
        "mission 'square_dance' initial=go @square_dance.yaml:1:1 path=square_dance.yaml"
        " description=''\n"
        "robot=None @None world=None @None\n"
        "- go @square_dance.yaml:2:3 timeout=None final=success description=''"
    )
    assert warnings == []


SHORT = """\
states:
  go:
    do: {play_tone: {frequency: 440 Hz, duration: 1 s}}
    on: {done: end, failed: end}
  end:
    final: success
"""


def test_mission_text_is_placed_in_a_file_named_mission() -> None:
    spec, warnings = parse_yaml_mission(SHORT)
    assert (spec.name, spec.path, warnings) == ("<mission>", "<mission>", [])
    with pytest.raises(MissionError) as info:
        parse_yaml_mission(SHORT.replace("play_tone", "play_tnoe"))
    assert info.value.format() == (
        "<mission>:3:10: error: unknown action 'play_tnoe' (did you mean 'play_tone'?)"
    )


def test_mission_text_that_is_not_yaml_is_a_mission_error() -> None:
    with pytest.raises(MissionError) as info:
        parse_yaml_mission("states: [\n", "m.yaml")
    assert info.value.format() == (
        "m.yaml:2:1: error: the file ends where a value was expected (close each `[` and `{`"
        " it opens)"
    )


def test_mission_text_is_checked_against_the_robot() -> None:
    from dataclasses import replace

    quiet = replace(get_profile("mirto"), name="quiet", capabilities=frozenset({"drive_base"}))
    with pytest.raises(MissionError) as info:
        parse_yaml_mission(SHORT, "m.yaml", quiet)
    assert info.value.format() == (
        "m.yaml:3:10: error: 'play_tone' needs speaker (a tone generator),"
        " which quiet does not have"
    )


def test_a_mission_file_loaded_before_can_be_used_by_another(tmp_path: Path) -> None:
    # A file is only "being loaded" while it loads: using it afterwards is no loop.
    path = write(
        tmp_path,
        {
            "m.yaml": "states:\n  go:\n    do: {mission: patrol.yaml}\n"
            "    on: {done: end, failed: end}\n  end:\n    final: success\n",
            "patrol.yaml": PATROL,
        },
    )
    load_yaml_mission(tmp_path / "patrol.yaml")
    assert report(path) == ["OK"]


def test_a_loop_through_another_file_is_named(tmp_path: Path) -> None:
    path = write(
        tmp_path,
        {
            "a.yaml": "states:\n  go:\n    do: {mission: b.yaml}\n"
            "    on: {done: end, failed: end}\n  end:\n    final: success\n",
            "b.yaml": "states:\n  go:\n    do: {mission: a.yaml}\n"
            "    on: {done: end, failed: end}\n  end:\n    final: success\n",
        },
    )
    assert report(path) == [
        "b.yaml:3:19: error: 'a.yaml' includes itself (directly or through another file)"
    ]


NESTED = """\
states:
  first:
    do: {mission: quick.yaml}
    on: {done: again}
  again:
    do: {mission: quick.yaml}
    on: {done: both}
  both:
    do: {parallel: {all: [{states: {a: {final: success}}}]}}
    on: {done: loop}
  loop:
    do: {repeat: {times: 1, do: {states: {r: {final: success}}}}}
    on: {done: nest}
  nest:
    do:
      states:
        n: {final: success}
    on: {done: end}
  end:
    final: success
"""


def test_inner_states_show_in_the_timeline_under_their_outer_state(tmp_path: Path) -> None:
    # The outer state's name is the prefix a student sees for each inner state, however the
    # inner machine was written: another file (twice: read once, used by both states),
    # inside parallel or repeat, or inline.
    path = write(tmp_path, {"m.yaml": NESTED, "quick.yaml": "states:\n  q:\n    final: success\n"})
    spec, warnings = load_yaml_mission(path)
    runner = MissionRunner(spec, {})
    for n in range(20):
        runner.tick(round(n * 0.1, 6), 0.1)
    assert (runner.finished, runner.result.outcome, warnings) == (True, "success", [])
    assert runner.result.states == [
        (0.0, "first"),
        (0.0, "first.q"),
        (0.0, "again"),
        (0.1, "again.q"),
        (0.1, "both"),
        (0.2, "both.a"),
        (0.2, "loop"),
        (0.3, "loop.r"),
        (0.3, "nest"),
        (0.4, "nest.n"),
        (0.4, "end"),
    ]


def test_an_actions_settings_written_as_one_value_are_shown_as_a_mapping_with_that_value(
    tmp_path: Path,
) -> None:
    for name, do in (
        ("a.yaml", "{rotate: 90 deg}"),
        ("b.yaml", "wait 2 s"),
        ("c.yaml", "{wait_until: bumper.any}"),
    ):
        (tmp_path / name).write_text(
            f"mission: m\nstates:\n  go:\n    do: {do}\n"
            "    on: {done: end, failed: end, timeout: end}\n  end: {final: success}\n",
            encoding="utf-8",
        )
    result = run_cli("check", "a.yaml", "b.yaml", "c.yaml", cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr.splitlines() == [
        (
            "a.yaml:4:18: error: the parameters of 'rotate' must be a mapping, each with its name"
            " (write `{rotate: {angle: 90 deg}}`)"
        ),
        (
            "b.yaml:4:9: error: 'do: wait 2 s' gives 'wait' its settings as plain text"
            " (write them as a mapping: do: {wait: {duration: 2 s}})"
        ),
        (
            "c.yaml:4:22: error: the parameters of 'wait_until' must be a mapping, each with its"
            " name (write `{wait_until: {condition: bumper.any, timeout: 10 s}}`)"
        ),
        "checked 3 files: 3 with errors",
    ]


@pytest.mark.parametrize(
    ("written", "expected"),
    [
        pytest.param(
            "{forward: {distance: 40 cm}}",
            "m.yaml:3:10: error: unknown action 'forward' (the action for that is 'drive')",
            id="a-word-for-an-action",
        ),
        pytest.param(
            "{forward: 40 cm}",
            "m.yaml:3:10: error: unknown action 'forward' (the action for that is 'drive')",
            id="a-word-for-an-action-with-its-value-alone",
        ),
        pytest.param(
            "{beep: {frequency: 440 Hz}}",
            "m.yaml:3:10: error: unknown action 'beep' (the action for that is 'play_tone')",
            id="beep",
        ),
        pytest.param(
            "{fly: {height: 2 m}}",
            "m.yaml:3:10: error: unknown action 'fly' (actions: display, drive, follow_line,"
            " follow_wall, motor, play_tone, rotate, servo, set_led, stop, turn, wait,"
            " wait_until, walk)",
            id="nothing-like-an-action",
        ),
    ],
)
def test_an_unknown_action_names_the_action_meant_or_the_actions_there_are(
    written: str, expected: str
) -> None:
    with pytest.raises(MissionError) as info:
        parse_yaml_mission(
            SHORT.replace("{play_tone: {frequency: 440 Hz, duration: 1 s}}", written), "m.yaml"
        )
    assert info.value.format() == expected


def test_an_initial_state_like_none_of_the_states_lists_them() -> None:
    with pytest.raises(MissionError) as info:
        parse_yaml_mission("initial: start\n" + SHORT, "m.yaml")
    assert info.value.format() == (
        "m.yaml:1:10: error: the initial state 'start' is not one of the states (the states:"
        " end, go)"
    )


@pytest.mark.parametrize(
    ("old", "new", "expected"),
    [
        pytest.param(
            "on: {done: end, failed: end}",
            "on: end",
            "m.yaml:4:9: error: 'on' maps outcomes to states, e.g. on: {done: next, timeout:"
            " stuck} (write on: {done: end})",
            id="on-with-a-state-alone",
        ),
        pytest.param(
            "on: {done: end, failed: end}",
            "on: {done:end}",
            "m.yaml:4:10: error: 'done:end' needs a space after its ':' (else YAML reads it as"
            " one word) (write done: end)",
            id="no-space-after-an-outcomes-colon",
        ),
        pytest.param(
            "on: {done: end, failed: end}",
            "on: {failed: end}\n    when: {if: bumper.any, goto: end}",
            "m.yaml:5:11: error: 'when' is a list of choices, each a condition and the state it"
            " goes to (write `when: [{if: bumper.any, goto: end}]`, one {...} per choice)",
            id="when-as-one-choice",
        ),
        pytest.param(
            "on: {done: end, failed: end}",
            "on: {failed: go}\n    when: [{if: elapsed > 1, then: end}]",
            "m.yaml:5:12: error: this choice needs 'goto', the state it goes to (write `goto:"
            " end`)",
            id="then-for-goto",
        ),
    ],
)
def test_a_transition_written_otherwise_is_answered_with_the_students_own_states(
    old: str, new: str, expected: str
) -> None:
    text = SHORT.replace(old, new)
    with pytest.raises(MissionError) as info:
        parse_yaml_mission(text, "m.yaml")
    problems = [p.format() for p in getattr(info.value, "problems", [info.value])]
    assert problems[0] == expected


@pytest.mark.parametrize("key", ["States", "state"])
def test_states_misspelt_is_told_once_with_the_key_meant(key: str) -> None:
    with pytest.raises(MissionError) as info:
        parse_yaml_mission(SHORT.replace("states:", f"{key}:"), "m.yaml")
    assert [p.format() for p in getattr(info.value, "problems", [info.value])] == [
        f"m.yaml:1:1: error: unknown key '{key}' in a mission (did you mean 'states'?)"
    ]


def test_a_mission_without_states_says_how_to_write_them() -> None:
    with pytest.raises(MissionError) as info:
        parse_yaml_mission("mission: m\ninitial: go\n", "m.yaml")
    assert info.value.format() == (
        "m.yaml:1:1: error: a mission needs 'states:', a mapping of state names to states (write"
        " states: and under it, indented, each state, e.g. go: {final: success})"
    )


def test_states_named_by_numbers_are_gone_to_by_their_numbers() -> None:
    spec, _ = parse_yaml_mission(
        "states:\n  1:\n    do: {wait: {duration: 1 s}}\n    on: {done: 2}\n"
        "    when: [{if: elapsed > 5, goto: 2}]\n  2: {final: success}\n",
        "m.yaml",
    )
    assert [t.target for t in spec.states["1"].on["done"]] == ["2"]
    assert [t.target for t in spec.states["1"].when] == ["2"]


@pytest.mark.parametrize(
    ("do", "written"),
    [
        ("{wait: 500}", "{wait: {duration: 500 ms}}"),
        ("{drive: 50}", "{drive: {distance: 50 cm}}"),
        ("{wait: 2}", "{wait: {duration: 2 s}}"),
    ],
)
def test_an_actions_bare_number_is_shown_as_a_mapping_with_the_unit_most_likely_meant(
    tmp_path: Path, do: str, written: str
) -> None:
    path = tmp_path / "m.yaml"
    path.write_text(
        f"mission: m\nstates:\n  go:\n    do: {do}\n    on: {{done: end, failed: end}}\n"
        "  end: {final: success}\n",
        encoding="utf-8",
    )
    (problem,) = problems(path)
    assert problem.endswith(f"must be a mapping, each with its name (write `{written}`)")


def _refused(text: str) -> str:
    """The first problem ``roboscript check`` tells of the YAML mission ``text``."""
    with pytest.raises(MissionError) as info:
        parse_yaml_mission(text, "m.yaml")
    return str(getattr(info.value, "problems", [info.value])[0].format())


@pytest.mark.parametrize(("word", "true"), sorted(YAML_1_1_WORDS.items()))
def test_each_yaml_1_1_word_for_true_or_false_is_told_as_meant_in_final_and_timeout(
    word: str, true: bool
) -> None:
    # one list of the words YAML 1.1 read as true or false, for every field told of them
    final = _refused(GOOD.replace("final: success", f"final: {word}"))
    assert f"'{word}' is a word here, not {'true' if true else 'false'}" in final
    timeout = _refused(GOOD.replace("on: {done", f"timeout: {word}\n    on: {{done"))
    assert ("is a word here: a state with no time limit" in timeout) is not true, timeout


def test_a_mission_of_many_states_is_read_in_work_linear_in_its_states(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # each state's examples (on:, a choice's goto:) looked through all the mission's states
    # for one to show: a search of every state for each state
    count = 2000
    lines = ["mission: m", "initial: s0", "states:"]
    lines += [
        f"  s{n}: {{do: {{wait: {{duration: 1 s}}}}, on: {{done: s{n + 1}}},"
        f" when: [{{if: bumper.any, goto: s{n + 1}}}]}}"
        for n in range(count)
    ]
    lines.append(f"  s{count}: {{final: success}}")
    looked_at = [0]

    def counted_min(items: Any) -> Any:
        items = list(items)
        looked_at[0] += len(items)
        return min(items)

    monkeypatch.setattr(yaml_loader, "min", counted_min, raising=False)
    spec, _ = parse_yaml_mission("\n".join(lines) + "\n", "m.yaml")
    assert len(spec.states) == count + 1
    assert looked_at[0] <= 2 * (count + 1)
