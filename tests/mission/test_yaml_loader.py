"""Golden messages for mistakes in mission files: file:line:col, what was meant, a hint."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from roboscript.errors import MissionError
from roboscript.mission import load_mission
from roboscript.profiles import RobotProfile, get_profile

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


def problems(path: Path, profile: RobotProfile | None = None) -> list[str]:
    with pytest.raises(MissionError) as info:
        load_mission(path, profile)
    found = getattr(info.value, "problems", [info.value])
    return [p.format().replace(str(path), "M") for p in found]


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
            "M:5:10: error: drive: drive needs a distance or a duration",
        ),
        (
            GOOD.replace("do: {drive: {distance: 30 cm}}", "do: {play_tone: {duration: 1 s}}"),
            "M:5:10: error: 'play_tone' needs 'frequency' (pitch)",
        ),
        (
            GOOD.replace(
                "do: {drive: {distance: 30 cm}}", 'do: {wait_until: {condition: "bumper.any"}}'
            ),
            (
                "M:5:10: error: 'wait_until' needs 'timeout' (the most it waits"
                " (every wait has a bound))"
            ),
        ),
        (
            GOOD.replace("do: {drive: {distance: 30 cm}}", "do: {follow_wall: {side: left}}"),
            (
                "M:5:10: error: 'follow_wall' in state 'go' never ends as written"
                " (give it 'until' or 'duration', or give the state a 'timeout' or a 'when')"
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
            "M:2:1: error: a mission needs 'states:', a mapping of state names to states",
        ),
        (
            "states:\n  a:\n    final: success\n  a:\n    final: failure\n",
            "M:4:3: error: 'a' is given twice (first on line 2)",
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
