"""One field reader for every YAML file: typed values, and mistakes at file:line:col."""

from __future__ import annotations

import pytest

from roboscript.errors import InputError, SpecError, WorldError
from roboscript.inputs.fields import FieldReader, unknown_key_hint
from roboscript.inputs.source import Location, load_yaml_text

TEXT = """\
speed: 15 cm/s
gap: -2 cm
count: 3
name: left
names: [a, b]
"""


def reader() -> FieldReader:
    return FieldReader("f.yaml", SpecError)


def fails(call: object, *args: object) -> str:
    with pytest.raises(InputError) as info:
        call(*args)  # type: ignore[operator]
    return str(info.value)


def test_values_are_read_with_their_units() -> None:
    data = load_yaml_text(TEXT)
    assert reader().quantity(data, "speed", "speed") == 150.0
    assert reader().quantity(data, "count", "time", "ms") == 0.003
    assert reader().integer(data, "count", 1) == 3
    assert reader().choice(data, "name", ("left", "right")) == "left"
    assert reader().names(data, "names") == [("a", (5, 9)), ("b", (5, 12))]
    assert reader().names(data, "name") == [("left", (4, 7))]
    assert reader().text(data, "name") == "left"


def test_wrong_values_are_errors_where_they_were_written() -> None:
    data = load_yaml_text(TEXT)
    assert fails(reader().positive, data, "gap", "distance") == (
        "f.yaml:2:6: error: 'gap' must be more than 0"
    )
    assert fails(reader().quantity, data, "speed", "angle").startswith(
        "f.yaml:1:8: error: 'cm/s' is a unit of speed, but this is an angle"
    )
    assert fails(reader().choice, data, "name", ("lift", "right")) == (
        "f.yaml:4:7: error: 'name' must be one of: lift, right (got 'left') (did you mean 'lift'?)"
    )
    assert fails(reader().integer, data, "count", 5) == (
        "f.yaml:3:8: error: 'count' must be a whole number of at least 5"
    )
    assert fails(reader().mapping, data["names"], "start", (5, 8)) == (
        "f.yaml:5:8: error: start must be a mapping such as {start: ...}"
    )
    assert fails(reader().items, data["name"], "runs", (4, 7)) == (
        "f.yaml:4:7: error: runs must be a list (one '- ' line per item)"
    )


def test_an_unknown_key_has_one_did_you_mean() -> None:
    data = load_yaml_text("sped: 1\nzzz: 2\n")
    found = [p.format() for p in reader().unknown_keys(data, ("speed", "gap"), "a run")]
    assert found == [
        "f.yaml:1:1: error: unknown key 'sped' in a run (did you mean 'speed'?)",
        "f.yaml:2:1: error: unknown key 'zzz' in a run (expected one of: speed, gap)",
    ]
    assert fails(reader().allowed, data, ("speed", "gap"), "a run").endswith(
        "(did you mean 'speed'?)"
    )
    # a word cut short means the key it begins
    assert unknown_key_hint("fina", ("max_time", "final_pose")) == "did you mean 'final_pose'?"


def test_a_required_key_is_asked_for_where_the_mapping_starts() -> None:
    data = load_yaml_text("runs:\n  - {seed: 1}\n")
    run = data["runs"][0]
    assert fails(reader().allowed, run, ("seed", "name"), "a run", ("name",)) == (
        "f.yaml:2:5: error: a run needs 'name'"
    )


def test_the_error_is_of_the_files_kind() -> None:
    problem = FieldReader("w.yaml", WorldError).fail("bad", (1, 2), "hint")
    assert isinstance(problem, WorldError) and problem.format() == "w.yaml:1:2: error: bad (hint)"
    elsewhere = FieldReader("w.yaml", WorldError).fail_at("bad", Location("other.yaml", 3, 4))
    assert elsewhere.format() == "other.yaml:3:4: error: bad"
    assert FieldReader("w.yaml").loc((2, 3)) == Location("w.yaml", 2, 3)
