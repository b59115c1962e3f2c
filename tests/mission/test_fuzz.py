"""Fuzzing the mission loader and the guard compiler: bad input gets a mission error, never a
traceback; nothing in a mission file can run code."""

from __future__ import annotations

import contextlib
import tracemalloc
from pathlib import Path

import pytest
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


# ----------------------------------------------------------------- generated hostile shapes
# The shapes of issue 17, generated rather than mutated: the campaign
# (tools/fuzz_campaign.py, docs/development/fuzzing.md) runs 10,000 of them; these run a few
# dozen on every test run.

HUGE = st.sampled_from(
    [
        "1e400",
        "-1e400",
        ".nan",
        ".inf",
        "9" * 5000,
        "-9.2e18",
        "-1e9",
        "2001-13-45",
        "0x" + "f" * 300,
    ]
)
WEIRD_TEXT = st.sampled_from(["x" * 5000, "\\ud800", "\\U0001F916", "\\t", "é", "\\x00"])


@st.composite
def hostile_missions(draw: st.DrawFn) -> str:
    shape = draw(
        st.sampled_from(["number", "nesting", "aliases", "type", "text", "tab", "state", "action"])
    )
    if shape == "number":
        key = draw(st.sampled_from(["distance", "speed", "duration", "frequency", "angle"]))
        action = {"distance": "drive", "speed": "drive", "duration": "wait"}.get(key, "rotate")
        action = "play_tone" if key == "frequency" else action
        do = f"{{{action}: {{{key}: {draw(HUGE)}}}}}"
        return f"states:\n  a:\n    do: {do}\n  b: {{final: success}}\n"
    if shape == "nesting":
        depth = draw(st.sampled_from([50, 500, 5000]))
        body = draw(
            st.sampled_from(["[" * depth + "]" * depth, "{a: " * depth + "1" + "}" * depth])
        )
        return f"states:\n  a: {{final: success}}\nx: {body}\n"
    if shape == "aliases":
        levels = draw(st.integers(3, 9))
        lines = ["a0: &a0 [x, x, x, x, x, x, x, x, x]"]
        lines += [f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * 9) + "]" for i in range(1, levels)]
        return "\n".join([*lines, "states: {a: {final: success}}"]) + "\n"
    if shape == "type":
        value = draw(st.sampled_from(["[1, 2]", "{a: 1}", "~", "true", "'ten'", "5"]))
        where = draw(st.sampled_from(["states", "initial", "do", "on", "when", "timeout"]))
        if where == "states":
            return f"states: {value}\n"
        return f"states:\n  a:\n    {where}: {value}\n  b: {{final: success}}\n"
    if shape == "text":
        return (
            f'mission: "{draw(WEIRD_TEXT)}"\nstates:\n  "{draw(WEIRD_TEXT)}": {{final: success}}\n'
        )
    if shape == "tab":
        return "states:\n\ta: {final: success}\n"
    if shape == "state":
        target = draw(st.sampled_from(["nowhere", "A", "'a '", '"\\ud800"']))
        return f"states:\n  a:\n    do: {{wait: {{duration: 1 s}}}}\n    on: {{done: {target}}}\n"
    name = draw(st.sampled_from(["fly", "drive_fast", "mission", "parallel", "repeat", "walk"]))
    do = f"{{{name}: {{x: 1}}}}"
    return f"states:\n  a:\n    do: {do}\n    on: {{done: b}}\n  b: {{final: success}}\n"


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(hostile_missions())
def test_generated_hostile_missions_give_located_errors_within_bounded_memory(text: str) -> None:
    tracemalloc.start()
    try:
        parse_yaml_mission(text, "fuzz.yaml")
    except InputError as exc:
        for line in exc.format().splitlines():
            assert line.startswith("fuzz.yaml:"), line
            assert "Traceback" not in line
    finally:
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
    assert peak < 256 * 1024 * 1024


def _conditions() -> st.SearchStrategy[str]:
    leaves = st.sampled_from(
        [
            "elapsed",
            "range.distance_cm",
            "bumper.any",
            "visits.a",
            "20",
            "1e400",
            "10**400",
            "1" + "0" * 400,
            "\ud800",
            "inf",
            "nan",
            "3 s",
            "true",
        ]
    )
    return st.recursive(
        leaves,
        lambda inner: st.one_of(
            st.tuples(inner, st.sampled_from(["<", "and", "or", "+", "/", "=="]), inner).map(
                " ".join
            ),
            inner.map(lambda c: f"({c})"),
            inner.map(lambda c: f"not {c}"),
        ),
        max_leaves=60,
    )


@settings(max_examples=150, deadline=None)
@given(st.one_of(_conditions(), st.integers(30, 3000).map(lambda n: "(" * n + "elapsed" + ")" * n)))
def test_generated_conditions_compile_or_explain_and_never_raise_when_run(source: str) -> None:
    try:
        guard = compile_guard(source, frozenset({"a"}))
    except GuardError as exc:
        assert 0 <= exc.offset <= len(source)
        assert "\n" not in str(exc)
        return
    assert isinstance(guard(_Env()), bool)


def _refusal(source: str) -> tuple[str, int, str | None]:
    try:
        compile_guard(source, frozenset())
    except GuardError as exc:
        return str(exc), exc.offset, exc.hint
    raise AssertionError(f"accepted: {source[:40]!r}")


def test_a_condition_may_be_1000_characters_long_but_not_1001() -> None:
    longest = "elapsed > 1".ljust(1000)
    assert compile_guard(longest, frozenset())(_Env()) is False
    assert _refusal(longest + " ") == (
        "a condition of 1001 characters is too long (at most 1000)",
        1000,
        "split it: a Python mission's condition method can hold longer logic",
    )


def test_a_condition_may_nest_32_deep_but_not_33() -> None:
    # 'not' k times over bumper.any: k operators, the attribute, its name and its context
    assert compile_guard("not " * 29 + "bumper.any", frozenset())(_Env()) is True
    assert _refusal("not " * 30 + "bumper.any") == (
        "the condition is nested more than 32 deep",
        0,
        "write it flatter: 'a and b and c' rather than brackets inside brackets",
    )


@pytest.mark.parametrize(
    ("char", "code"), [("\ud800", "D800"), ("\udbff", "DBFF"), ("\udfff", "DFFF")]
)
def test_a_lone_surrogate_in_a_condition_is_named_where_it_is(char: str, code: str) -> None:
    assert _refusal(f"elapsed > {char}") == (
        f"the condition holds U+{code}, which is not a character",
        10,
        None,
    )
