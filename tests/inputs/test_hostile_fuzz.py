"""Generated hostile YAML (deep nesting, aliases, huge numbers, odd unicode, tabs, unclosed
brackets): the input layer raises an ``InputError`` and nothing else, and what it accepts stays
within the value and depth budget, so the work any file can cause is bounded."""

from __future__ import annotations

from typing import Any

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from roboscript.errors import InputError
from roboscript.inputs.limits import MAX_DEPTH, MAX_VALUES
from roboscript.inputs.source import load_yaml_text
from roboscript.mission.yaml_loader import parse_yaml_mission

SCALARS = st.sampled_from(
    [
        "1",
        "-0.5",
        "50 cm",
        "0,2 m/s",
        "1.0e+400",
        ".inf",
        ".nan",
        "2024-13-45",
        "=",
        "on",
        "~",
        "'quoted'",
        '"dq\\u00e9"',
        "é∑😀",
        "\u202e",
        "!!float abc",
        "!!timestamp x",
        "!!python/object:os.system x",
    ]
)


@st.composite
def huge_numbers(draw: st.DrawFn) -> str:
    digits = draw(st.integers(1, 6000))
    return draw(st.sampled_from(["", "-", "+"])) + "9" * digits + draw(st.sampled_from(["", " mm"]))


@st.composite
def nested(draw: st.DrawFn) -> str:
    depth = draw(st.integers(1, 3 * MAX_DEPTH))
    inner = draw(SCALARS)
    if draw(st.booleans()):
        return "[" * depth + inner + "]" * depth
    return "{k: " * depth + inner + "}" * depth


@st.composite
def alias_bombs(draw: st.DrawFn) -> str:
    levels = draw(st.integers(1, 12))
    fan_out = draw(st.integers(1, 12))
    lines = [f"l0: &l0 [{draw(SCALARS)}]"]
    for level in range(1, levels):
        lines.append(f"l{level}: &l{level} [" + ",".join([f"*l{level - 1}"] * fan_out) + "]")
    if draw(st.booleans()):  # an alias inside its own anchor
        lines.append("loop: &loop [*loop]")
    return "\n".join(lines)


FRAGMENTS = st.one_of(SCALARS, huge_numbers(), nested(), alias_bombs())


@st.composite
def hostile_documents(draw: st.DrawFn) -> str:
    parts = draw(st.lists(FRAGMENTS, min_size=1, max_size=4))
    text = "\n".join(f"k{i}: {part}" if "\n" not in part else part for i, part in enumerate(parts))
    for _ in range(draw(st.integers(0, 3))):
        position = draw(st.integers(0, len(text)))
        piece = draw(
            st.sampled_from(["\t", "  ", "{", "[", '"', "'", "\n", ": ", "*l0", "&a ", "\ud800"])
        )
        if draw(st.booleans()):
            text = text[:position] + piece + text[position:]
        else:  # drop a character: often a closing bracket or quote
            text = text[:position] + text[position + 1 :]
    return text + "\n"


def values_and_depth(data: Any) -> tuple[int, int]:
    """Values in ``data`` counting each shared object at each use, as an alias is counted;
    stops one past the budget, so a runaway result cannot make the test itself run away."""
    count, deepest = 0, 0
    stack: list[tuple[Any, int]] = [(data, 1)]
    while stack and count <= MAX_VALUES:
        value, depth = stack.pop()
        count += 1
        if isinstance(value, dict):
            deepest = max(deepest, depth)
            count += len(value)  # the keys
            stack.extend((item, depth + 1) for item in value.values())
        elif isinstance(value, list):
            deepest = max(deepest, depth)
            stack.extend((item, depth + 1) for item in value)
    return count, deepest


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(hostile_documents())
def test_hostile_yaml_is_an_input_error_or_within_the_budget(text: str) -> None:
    try:
        data = load_yaml_text(text, "h.yaml")
    except InputError as exc:
        assert exc.path == "h.yaml"
        assert "\n" not in exc.format()  # one located line
        return
    count, depth = values_and_depth(data)
    assert count <= MAX_VALUES
    assert depth <= MAX_DEPTH


MISSION = """\
mission: hostile
description:
DESCRIPTION
initial: go
states:
  go:
    do: {drive: {distance: DISTANCE}}
    on: {done: end}
  end: {final: success}
"""


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(FRAGMENTS, FRAGMENTS)
def test_a_hostile_value_in_a_mission_is_a_mission_problem(description: str, distance: str) -> None:
    block = "\n".join(f"  {line}" for line in description.splitlines())
    text = MISSION.replace("DESCRIPTION", block).replace("DISTANCE", distance.replace("\n", " "))
    try:
        parse_yaml_mission(text, "m.yaml")
    except InputError as exc:
        assert exc.path == "m.yaml"
