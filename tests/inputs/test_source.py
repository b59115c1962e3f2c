"""Safe YAML with positions: where every key, value and item was written."""

from __future__ import annotations

from pathlib import Path

import pytest

from roboscript.errors import InputError, WorldError
from roboscript.inputs.source import Location, YamlList, YamlMap, load_yaml, load_yaml_text

TEXT = """\
name: demo
speed: "15 cm/s"
items:
  - a
  - {b: 1}
nested:
  inner: on
"""


def test_mappings_and_lists_know_where_each_item_was_written() -> None:
    data = load_yaml_text(TEXT, "f.yaml")
    assert isinstance(data, YamlMap)
    assert data.mark == (1, 1)
    assert data.key_mark("speed") == (2, 1) and data.value_mark("speed") == (2, 8)
    assert data.key_mark("absent") == data.mark == data.value_mark("absent")
    items = data["items"]
    assert isinstance(items, YamlList) and items.item_marks == [(4, 5), (5, 5)]
    assert items[1].key_mark("b") == (5, 6)


def test_text_marks_step_inside_quotes() -> None:
    data = load_yaml_text(TEXT)
    assert data.text_mark("speed") == (2, 9)  # the '1' after the opening quote
    assert data.text_mark("speed", 3) == (2, 12)
    assert data.text_mark("name", 2) == (1, 9)  # unquoted


def test_only_true_and_false_are_booleans() -> None:
    data = load_yaml_text(TEXT)
    assert data["nested"]["inner"] == "on"
    assert load_yaml_text("a: true\nb: False\nc: yes\n") == {"a": True, "b": False, "c": "yes"}


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (
            "a: 1\na: 2\n",
            (
                "f.yaml:2:1: error: 'a' is given twice (first on line 1) (keep one of the two, or"
                " give one of them another name)"
            ),
        ),
        ("a: !!python/object:os.system x\n", "f.yaml:1:4: error: tag"),
        ("a: [1, 2\n", "f.yaml:1:4: error: this `[` is never closed"),
        ("a: 1\x07\n", "f.yaml:1:5: error: the file contains a character YAML does not allow"),
    ],
)
def test_bad_yaml_is_an_error_at_file_line_col(text: str, expected: str) -> None:
    with pytest.raises(InputError) as info:
        load_yaml_text(text, "f.yaml")
    assert str(info.value).startswith(expected)


def test_the_error_is_of_the_kind_asked_for(tmp_path: Path) -> None:
    with pytest.raises(WorldError):
        load_yaml_text("a: 1\na: 2\n", "w.yaml", error=WorldError)
    with pytest.raises(WorldError, match="cannot read the file"):
        load_yaml(tmp_path / "absent.yaml", error=WorldError)
    (tmp_path / "latin.yaml").write_bytes(b"a: \xe9\n")
    with pytest.raises(WorldError, match="not UTF-8"):
        load_yaml(tmp_path / "latin.yaml", error=WorldError)


def test_a_location_names_the_file_line_and_column() -> None:
    assert str(Location("m.yaml", 3, 7)) == "m.yaml:3:7"
    assert str(Location("m.yaml", 3)) == "m.yaml:3"
    assert str(Location("m.yaml")) == "m.yaml"
    assert Location.at("m.yaml", (3, 7)) == Location("m.yaml", 3, 7)
    assert Location.at("m.yaml", None) == Location("m.yaml")
