"""Fuzzing the mission loader and the guard compiler: bad input gets a mission error, never a
traceback; nothing in a mission file can run code."""

from __future__ import annotations

import contextlib
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from roboscript.errors import InputError
from roboscript.mission.guards import GuardEnv, GuardError, compile_guard
from roboscript.mission.yaml_loader import parse_yaml_mission

SEED_MISSIONS = [
    p.read_text(encoding="utf-8")
    for p in sorted((Path(__file__).resolve().parents[2] / "missions").glob("*.yaml"))
]


@st.composite
def mutated_missions(draw: st.DrawFn) -> str:
    text = draw(st.sampled_from(SEED_MISSIONS))
    for _ in range(draw(st.integers(1, 4))):
        position = draw(st.integers(0, len(text)))
        kind = draw(st.sampled_from(["replace", "insert", "delete", "duplicate_line"]))
        piece = draw(
            st.sampled_from(
                [
                    ":",
                    "{",
                    "}",
                    "[",
                    "-",
                    " ",
                    "\n",
                    "'",
                    '"',
                    "!!python/object:os.system",
                    "*a",
                    "&a",
                    "0",
                    "deg",
                    "?",
                    "\t",
                    "\x00",
                    "é",
                    "states",
                    "do",
                ]
            )
        )
        if kind == "replace":
            text = text[:position] + piece + text[position + 1 :]
        elif kind == "insert":
            text = text[:position] + piece + text[position:]
        elif kind == "delete":
            text = text[:position] + text[position + len(piece) :]
        else:
            lines = text.splitlines(keepends=True)
            if lines:
                index = draw(st.integers(0, len(lines) - 1))
                lines.insert(index, lines[index])
                text = "".join(lines)
    return text


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated_missions())
def test_mutated_missions_give_mission_errors_only(text: str) -> None:
    try:
        parse_yaml_mission(text, "fuzz.yaml")
    except InputError as exc:
        assert exc.format().startswith("fuzz.yaml")


@settings(max_examples=300, deadline=None)
@given(st.text(max_size=200))
def test_arbitrary_text_is_a_mission_error_or_a_mission(text: str) -> None:
    with contextlib.suppress(InputError):
        parse_yaml_mission(text, "fuzz.yaml")


TOKENS = [
    "range.distance_cm",
    "range.distance_mm",
    "bumper.any",
    "bumper.left",
    "line.center",
    "line.any",
    "heading_deg",
    "elapsed",
    "state_time",
    "visits.a",
    "visits.zz",
    "20",
    "0",
    "1.5",
    "-3",
    "20 cm",
    "3 s",
    "90 deg",
    "<",
    "<=",
    ">",
    ">=",
    "==",
    "!=",
    "and",
    "or",
    "not",
    "+",
    "-",
    "*",
    "/",
    "(",
    ")",
    "true",
    "false",
    "__class__",
    ".",
    "'x'",
    "[",
    "]",
    "lambda",
    "import",
    "os",
    "eval",
    ",",
    "**",
    "%",
    "if",
    "else",
]


class _Env(GuardEnv):
    def sensor(self, root: str, attr: str | None) -> float | bool:
        if root in ("bumper",) or attr == "any":
            return False
        return 0.0

    def visits(self, state: str) -> int:
        return 0


@settings(max_examples=600, deadline=None)
@given(st.lists(st.sampled_from(TOKENS), min_size=1, max_size=9))
def test_guard_compiler_accepts_or_explains_and_evaluation_never_raises(tokens: list[str]) -> None:
    source = " ".join(tokens)
    try:
        guard = compile_guard(source, frozenset({"a"}))
    except GuardError as exc:
        assert 0 <= exc.offset <= len(source)
        return
    assert isinstance(guard(_Env()), bool)


def test_division_by_zero_in_a_guard_is_infinite_not_an_error() -> None:
    assert compile_guard("elapsed / 0 > 1000")(_Env()) is False  # 0/0 is nan: compares false
    assert compile_guard("(elapsed + 1) / 0 > 1000")(_Env()) is True
    assert compile_guard("elapsed / 0 < 0 or elapsed / 0 >= 0")(_Env()) is False  # nan


def test_nothing_in_a_mission_file_runs_code(tmp_path: Path) -> None:
    marker = tmp_path / "pwned"
    attempts = [
        (
            f"mission: !!python/object/apply:os.system ['touch {marker}']\n"
            "states: {a: {final: success}}\n"
        ),
        f"states:\n  a: !!python/object/new:os.system ['touch {marker}']\n",
        (
            "states:\n  a:\n    do: {wait: {duration: 1 s}}\n    on:\n      done:\n"
            f"        - {{if: \"__import__('os').system('touch {marker}')\", goto: a}}\n"
        ),
        (
            "states:\n  a:\n    do: {wait: {duration: 1 s}}\n    on:\n      done:\n"
            '        - {if: "range.__class__.__base__", goto: a}\n'
        ),
        (
            "states:\n  a:\n    do: {wait: {duration: 1 s}}\n    on:\n      done:\n"
            "        - {if: 'builtins.print', goto: a}\n"
        ),
    ]
    for text in attempts:
        try:
            parse_yaml_mission(text, "attack.yaml")
        except InputError:
            pass
        else:
            raise AssertionError(f"accepted: {text!r}")
    assert not marker.exists()
