"""Quantities with units, as students and teachers write them."""

from __future__ import annotations

import math

import pytest

from roboscript.inputs.quantities import (
    QuantityError,
    clock_reading,
    parse_quantity,
    without_leading_zeros,
)


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


@pytest.mark.parametrize(
    ("text", "dimension", "meant"),
    [
        ("10 centimeters", "distance", "write 10 cm"),
        ("10 centimetres", "distance", "write 10 cm"),
        ("10 inches", "distance", "write 10 in"),
        ("10 cms", "distance", "write 10 cm"),
        ("10cm.", "distance", "write 10 cm"),
        ("50 cm's", "distance", "write 50 cm"),
        ("1 foot", "distance", "write 12 in"),
        ("5 dm", "distance", "write 50 cm"),
        ("10 metros", "distance", "write 10 m"),
        ("90º", "angle", "write 90 deg"),
        ("90 degres", "angle", "write 90 deg"),
        ("1 turn", "angle", "write 360 deg"),
        ("2 secs", "time", "write 2 s"),
        ("2 seconds", "time", "write 2 s"),
        ("440 hertz", "frequency", "write 440 Hz"),
        ("10 cm per second", "speed", "write 10 cm/s"),
        ("10 centimeters per second", "speed", "write 10 cm/s"),
        ("10 cm/sec", "speed", "write 10 cm/s"),
        ("1 km/h", "speed", "write 27.78 cm/s"),
    ],
)
def test_a_unit_written_out_or_another_way_is_told_how_roboscript_writes_it(
    text: str, dimension: str, meant: str
) -> None:
    with pytest.raises(QuantityError) as info:
        parse_quantity(text, dimension)
    assert info.value.hint == meant


@pytest.mark.parametrize(
    ("text", "dimension", "meant"),
    [
        ("1/2 m", "distance", "a quantity is one number and its unit: write 0.5 m"),
        ("3/4 centimeters", "distance", "a quantity is one number: write 0.75 cm"),
        ("1/4 turn", "angle", "a quantity is one number: write 90 deg"),
    ],
)
def test_a_quantity_written_as_a_fraction_is_told_as_one_number(
    text: str, dimension: str, meant: str
) -> None:
    with pytest.raises(QuantityError) as info:
        parse_quantity(text, dimension)
    assert info.value.message == f"'{text}' is a fraction"
    assert info.value.hint == meant


@pytest.mark.parametrize(
    ("written", "plain"),
    [("010", "10"), ("-007", "-7"), ("+0_10", "10"), ("00", "0"), ("0_0", "0")],
)
def test_a_number_without_its_leading_zeros_keeps_its_sign_and_drops_its_underscores(
    written: str, plain: str
) -> None:
    assert without_leading_zeros(written) == plain


@pytest.mark.parametrize(
    ("written", "read"),
    [
        ("1:30", (90.0, "1 min 30 s")),
        ("-1:00:30", (-3630.0, "-1 h 30 s")),
        ("0:00", (0.0, None)),
        ("1:2:3:4", (223384.0, None)),
        ("1.30", None),
    ],
)
def test_a_clock_reads_its_seconds_and_its_units(
    written: str, read: tuple[float, str | None] | None
) -> None:
    assert clock_reading(written) == read
