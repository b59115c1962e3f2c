"""Keys from other tools or from the Python form, written in a mission: the hint shows the line
to write, with the student's own value, through the real ``roboscript check``."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers import refusal, run_cli

from roboscript.mission.key_mistakes import meant_in_state_call

YAML_MIXUPS = [
    (
        "name: square\nstates:\n  go: {final: success}\n",
        (
            "M:1:1: error: unknown key 'name' in a mission"
            " (a mission's name goes under 'mission:': write mission: square)"
        ),
    ),
    (
        "start: go\nstates:\n  go: {final: success}\n",
        (
            "M:1:1: error: unknown key 'start' in a mission"
            " (the first state is named under 'initial:': write initial: go)"
        ),
    ),
    (
        (
            "states:\n  go:\n    action: {drive: {distance: 50 cm}}\n    on: {done: end}\n"
            "  end: {final: success}\n"
        ),
        (
            "M:3:5: error: unknown key 'action' in state 'go'"
            " (a state's action goes under 'do:': write do: {drive: {...}})"
        ),
    ),
    (
        (
            "states:\n  go:\n    do: {drive: {distance: 50 cm}}\n    next: end\n"
            "  end: {final: success}\n"
        ),
        (
            "M:4:5: error: unknown key 'next' in state 'go'"
            " (where a state goes next is written under 'on:', by outcome: write on: {done: end})"
        ),
    ),
    (
        (
            "states:\n  go:\n    do: {drive: {distance: 50 cm}}\n    on_failed: end\n"
            "  end: {final: success}\n"
        ),
        (
            "M:4:5: error: unknown key 'on_failed' in state 'go'"
            " (outcomes go under 'on:': write on: {failed: end})"
        ),
    ),
    (
        (
            "states:\n  go:\n    do: {drive: {distance: 50 cm}}\n"
            "    transitions: {done: end, timeout: go}\n  end: {final: success}\n"
        ),
        (
            "M:4:5: error: unknown key 'transitions' in state 'go' (where a state goes next is"
            " written under 'on:', by outcome: write on: {done: end, timeout: go})"
        ),
    ),
    (
        (
            "states:\n  go:\n    do: {drive: {distance: 50 cm}}\n    on: {done: end}\n"
            "  end:\n    end: success\n"
        ),
        (
            "M:6:5: error: unknown key 'end' in state 'end'"
            " (a state that ends the mission says so under 'final:': write final: success)"
        ),
    ),
]


@pytest.mark.parametrize(("text", "expected"), YAML_MIXUPS)
def test_a_key_from_another_tool_gets_the_line_to_write(
    tmp_path: Path, text: str, expected: str
) -> None:
    path = tmp_path / "m.yaml"
    path.write_text(text, encoding="utf-8")
    assert expected in refusal(path)


def test_a_slip_of_spelling_still_gets_did_you_mean(tmp_path: Path) -> None:
    path = tmp_path / "m.yaml"
    path.write_text("stats:\n  go: {final: success}\n", encoding="utf-8")
    assert "M:1:1: error: unknown key 'stats' in a mission (did you mean 'states'?)" in refusal(
        path
    )


def test_the_python_forms_state_gets_the_same_help(tmp_path: Path) -> None:
    path = tmp_path / "m.py"
    path.write_text(
        "from roboscript import Drive, Mission, state\n\n\n"
        "class Go(Mission):\n"
        '    go = state(Drive(distance_mm=500), initial=True, next="end")\n'
        '    end = state(final="success")\n',
        encoding="utf-8",
    )
    result = run_cli("check", str(path))
    assert result.returncode == 2
    assert (
        f"{path}:5:10: error: state() has no parameter 'next'"
        ' (where a state goes next is named by outcome: write on_done="NEXT")'
    ) in result.stderr


@pytest.mark.parametrize(
    ("keyword", "meant"),
    [("on_finished", "on_done"), ("on_success", "on_done"), ("on_error", "on_failed")],
)
def test_a_python_states_word_for_an_outcome_names_the_outcome(keyword: str, meant: str) -> None:
    assert meant_in_state_call(keyword) == f'write {meant}="NEXT"'


def test_a_states_keys_written_as_a_list_are_told_to_lose_their_dashes(tmp_path: Path) -> None:
    path = tmp_path / "m.yaml"
    path.write_text(
        "mission: m\nstates:\n  go:\n    - do: {drive: {distance: 50 cm}}\n"
        "    - on: {done: end}\n  end: {final: success}\n",
        encoding="utf-8",
    )
    assert refusal(path) == [
        (
            "M:4:5: error: state 'go' must be a mapping (do:, on:, when:, final:) (write do: and"
            " on: without the '- ' before them: a state's keys are one under the other, not a"
            " list)"
        )
    ]
