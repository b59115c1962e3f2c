"""YAML mistakes a beginner makes, explained in their terms at ``file:line:col``."""

from __future__ import annotations

import pytest

from roboscript.errors import InputError
from roboscript.inputs.source import load_yaml_text


def refused(text: str) -> InputError:
    with pytest.raises(InputError) as info:
        load_yaml_text(text, "f.yaml")
    return info.value


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("states:\n\tgo: {}\n", "f.yaml:2:1: error: a tab at 2:1: YAML indents with spaces"),
        ("a:\n  b: 1\n  \tc: 2\n", "f.yaml:3:3: error: a tab at 3:3: YAML indents with spaces"),
        ("a:\n\t- x\n", "f.yaml:2:1: error: a tab at 2:1: YAML indents with spaces"),
        ("a:\t1\n", "f.yaml:1:3: error: a tab at 1:3: YAML needs spaces here, not tabs"),
    ],
)
def test_a_tab_says_yaml_wants_spaces(text: str, expected: str) -> None:
    assert str(refused(text)) == expected


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        # at the end of the file
        ("a: {b: 1\n", "f.yaml:1:4: error: this `{` is never closed (close it with `}`)"),
        ("a: [1, 2\n", "f.yaml:1:4: error: this `[` is never closed (close it with `]`)"),
        # noticed lines later: still the opening bracket
        (
            "do: {drive: {distance: 50 cm}\nnext: 1\n",
            "f.yaml:1:5: error: this `{` is never closed (close it with `}` before 2:1)",
        ),
        # closed with the other bracket
        ("a: {b: [1, 2}\n", "f.yaml:1:8: error: this `[` is never closed (close it with `]`"),
        (
            'a: "abc\nb: 2\n',
            'f.yaml:1:4: error: this `"` is never closed (close the text with `"`)',
        ),
        (
            "x: 1\na: 'abc\n",
            "f.yaml:2:4: error: this `'` is never closed (close the text with `'`)",
        ),
    ],
)
def test_an_unclosed_bracket_or_quote_is_shown_where_it_opens(text: str, expected: str) -> None:
    assert str(refused(text)).startswith(expected)


def test_a_missing_comma_on_one_line_is_not_called_unclosed() -> None:
    assert str(refused("a: {b: 1 c: 2}\n")) == (
        "f.yaml:1:11: error: expected `,` or `}` here (inside the `{` at 1:4)"
    )


INDENT_HINT = (
    "YAML nests by indentation: line it up, with spaces, with the key or '- ' item it belongs with"
)


@pytest.mark.parametrize(
    ("text", "where"),
    [
        ("states:\n  go:\n    do: x\n   final: success\n", (4, 4)),
        ("a:\n  b: 1\n c: 2\n", (3, 2)),
        ("a:\n  - x\n - y\n", (3, 2)),
    ],
)
def test_a_line_indented_wrongly_gets_a_hint(text: str, where: tuple[int, int]) -> None:
    error = refused(text)
    assert (error.line, error.col) == where
    assert error.message == "this line is indented differently from the lines above it"
    assert error.hint == INDENT_HINT


def test_a_line_indented_too_far_gets_a_hint() -> None:
    error = refused("a: 1\n  b: 2\n")
    assert str(error) == (
        "f.yaml:2:4: error: a ':' is not allowed here (is this line indented further than the"
        " one above it? Text holding ': ' goes in quotes)"
    )


def test_a_key_without_its_colon_is_shown_at_the_key() -> None:
    assert str(refused("a: 1\nb\nc: 2\n")) == (
        "f.yaml:2:1: error: this line needs a ':' after its key"
        " (write 'key: value', or indent it as part of the line above)"
    )


def test_an_undefined_alias_says_so() -> None:
    assert str(refused("a: *x\n")) == (
        "f.yaml:1:4: error: the alias *x names no anchor &x written before it"
    )


def test_a_decimal_comma_in_a_flow_mapping_is_caught_before_yaml_splits_it() -> None:
    assert str(refused("do: {drive: {distance: 50 cm, speed: 0,2 m/s}}\n")) == (
        "f.yaml:1:38: error: '0,2 m/s' has a decimal comma, which YAML reads as two items"
        " (use a decimal point: 0.2 m/s)"
    )
    # a list of numbers is a list, and a key after a comma and a space is a key
    assert load_yaml_text("a: [0,2]\nb: {x: 0, 2: y}\n") == {"a": [0, 2], "b": {"x": 0, "2": "y"}}


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (
            "do: {rotate: {angle: - 90 deg}}\n",
            (
                "f.yaml:1:22: error: '- ' starts a list item, and a list cannot go here (a negative"
                " number has no space after its minus: write -90 deg, not - 90 deg)"
            ),
        ),
        (
            "rotate:\n  angle: - 90 deg\n",
            (
                "f.yaml:2:10: error: '- ' starts a list item, and a list cannot go here (a negative"
                " number has no space after its minus: write -90 deg, not - 90 deg)"
            ),
        ),
        (
            "on: {done: end,, failed: end}\n",
            (
                "f.yaml:1:16: error: a value is missing before this `,` (write a value, or remove"
                " the comma)"
            ),
        ),
        (
            "mission: a\n---\nmission: b\n",
            (
                "f.yaml:2:1: error: this file holds a second document after `---`, and a roboscript"
                " file holds one (remove the `---` line and what follows it, or move that to a file"
                " of its own)"
            ),
        ),
        (
            "mission: @home\n",
            (
                "f.yaml:1:10: error: '@' cannot start a value in YAML (put the text in quotes:"
                ' "@...")'
            ),
        ),
        (
            "mission: &\n",
            (
                "f.yaml:1:10: error: '&' at the start of a value is a sign YAML reads, not text"
                ' (put the text in quotes: "&...")'
            ),
        ),
        (
            'path: "C:\\missions"\n',
            (
                'f.yaml:1:10: error: inside "..." a backslash starts an escape such as \\n'
                " (write the text in single quotes, 'like\\this', or use / instead of \\)"
            ),
        ),
        (
            "do: {drive: {distance: 4 cm}}}\n",
            ("f.yaml:1:30: error: this `}` closes a `{` that was never opened (remove it)"),
        ),
    ],
)
def test_yamls_own_words_never_reach_the_student(text: str, expected: str) -> None:
    assert str(refused(text)) == expected
