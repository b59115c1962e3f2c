"""Quantities with units, as students and teachers write them."""

from __future__ import annotations

import math

import pytest

from roboscript.inputs.quantities import QuantityError, parse_quantity


@pytest.mark.parametrize(
    ("value", "dimension", "expected"),
    [
        ("50 cm", "distance", 500.0),
        ("-1.5 m", "distance", -1500.0),
        ("2 in", "distance", 50.8),
        (300, "distance", 300.0),
        ("15 cm/s", "speed", 150.0),
        ("200 ms", "time", 0.2),
        ("1 min", "time", 60.0),
        ("90 deg", "angle", 90.0),
        ("90°", "angle", 90.0),
        ("1 rev", "angle", 360.0),
        ("10 rpm", "turn_rate", 60.0),
        ("880 Hz", "frequency", 880.0),
        ("1 kHz", "frequency", 1000.0),
        ("1e3 mm", "distance", 1000.0),
    ],
)
def test_units_convert_to_the_base_unit(value: object, dimension: str, expected: float) -> None:
    assert math.isclose(parse_quantity(value, dimension), expected)


def test_a_bare_number_takes_the_fields_unit() -> None:
    assert parse_quantity(2, "time", "ms") == 0.002
    assert parse_quantity("30", "distance", "cm") == 300.0
    assert parse_quantity(30, "distance") == 30.0


@pytest.mark.parametrize(
    ("value", "dimension", "message"),
    [
        ("50 deg", "speed", "'deg' is a unit of angle, but this is a speed (use mm/s"),
        ("5 parsecs", "distance", "unknown unit 'parsecs' for a distance (use mm, cm, m, in)"),
        ("fast", "speed", "expected a speed such as '15 cm/s', got 'fast'"),
        (True, "time", "expected a time, got True"),
        ([1], "angle", "expected an angle such as '90 deg', got [1]"),
    ],
)
def test_a_wrong_quantity_says_what_would_fit(value: object, dimension: str, message: str) -> None:
    with pytest.raises(QuantityError) as info:
        parse_quantity(value, dimension)
    assert str(info.value).startswith(message)


@pytest.mark.parametrize(
    ("text", "meant"), [("5O cm", "50 cm"), ("1OO mm", "100 mm"), ("2o", "20")]
)
def test_a_letter_o_typed_for_a_zero_is_named_with_the_number_meant(text: str, meant: str) -> None:
    with pytest.raises(QuantityError) as refused:
        parse_quantity(text, "distance")
    assert refused.value.hint == f"write {meant}"
    assert "where a zero was meant" in refused.value.message


def test_a_unit_starting_with_o_after_a_space_is_an_unknown_unit() -> None:
    with pytest.raises(QuantityError, match="unknown unit 'Oranges'"):
        parse_quantity("3 Oranges", "distance")
