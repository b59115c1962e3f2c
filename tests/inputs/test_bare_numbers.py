"""Quantities for beginners: a bare number is taken in the field's unit, with a warning that
says so; a decimal comma gets its own hint; only finite quantities are read."""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest
from helpers import HANG_BOUND_S

from roboscript.errors import InputError, WorldError
from roboscript.inputs.fields import FieldReader
from roboscript.inputs.quantities import QuantityError, bare_number_warning, parse_quantity
from roboscript.inputs.source import load_yaml_text
from roboscript.mission import load_mission

MISSIONS = Path(__file__).resolve().parents[2] / "missions"


@pytest.mark.parametrize(
    ("value", "dimension", "expected"),
    [
        (50, "distance", ("50 taken as 50 mm; write `50 mm`", "or did you mean 50 cm?")),
        ("50", "distance", ("50 taken as 50 mm; write `50 mm`", "or did you mean 50 cm?")),
        (0.5, "distance", ("0.5 taken as 0.5 mm; write `0.5 mm`", "or did you mean 0.5 cm?")),
        (150, "speed", ("150 taken as 150 mm/s; write `150 mm/s`", "or did you mean 150 cm/s?")),
        (200, "time", ("200 taken as 200 s; write `200 s`", "or did you mean 200 ms?")),
        (10, "time", ("10 taken as 10 s; write `10 s`", None)),
        (90, "angle", ("90 taken as 90 deg; write `90 deg`", None)),
        (30, "turn_rate", ("30 taken as 30 deg/s; write `30 deg/s`", None)),
        (880, "frequency", ("880 taken as 880 Hz; write `880 Hz`", None)),
    ],
)
def test_a_bare_number_where_the_unit_matters_is_named_with_its_unit(
    value: object, dimension: str, expected: tuple[str, str | None]
) -> None:
    assert bare_number_warning(value, dimension) == expected


def test_the_warning_names_the_fields_own_unit() -> None:
    assert bare_number_warning(30, "distance", "cm") == ("30 taken as 30 cm; write `30 cm`", None)


@pytest.mark.parametrize(
    ("value", "dimension"),
    [
        ("50 cm", "distance"),
        (0, "distance"),  # zero is zero in every unit
        ("0", "speed"),
        (40, "percent"),
        (3, "count"),
        (True, "distance"),
        ("fast", "speed"),
        (float("inf"), "distance"),
    ],
)
def test_no_warning_when_the_unit_is_written_or_does_not_matter(
    value: object, dimension: str
) -> None:
    assert bare_number_warning(value, dimension) is None


def test_a_decimal_comma_gets_its_own_hint() -> None:
    with pytest.raises(QuantityError) as info:
        parse_quantity("0,2 m/s", "speed")
    assert (info.value.message, info.value.hint) == (
        "'0,2 m/s' has a decimal comma",
        "use a decimal point: 0.2 m/s",
    )
    assert str(info.value) == "'0,2 m/s' has a decimal comma (use a decimal point: 0.2 m/s)"


def test_reading_a_long_quantity_is_refused_not_backtracked() -> None:
    # "1" * 20000 + "\n1" took 30 s with the old pattern; now it is refused by its length.
    with pytest.raises(QuantityError, match="got 20002 characters"):
        parse_quantity("1" * 20000 + "\n1", "distance")
    with pytest.raises(QuantityError, match="expected a distance such as '50 cm'"):
        parse_quantity("1" * 50 + "\n1", "distance")


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("x: 1.0e+400\n", "w.yaml:1:4: error: infinity is not a distance a robot can use"),
        ("x: -.inf\n", "w.yaml:1:4: error: -infinity is not a distance a robot can use"),
        ("x: .nan\n", "w.yaml:1:4: error: nan is not a distance a robot can use"),
        ("x: 1e400 mm\n", "w.yaml:1:4: error: '1e400 mm' is not a distance a robot can use"),
    ],
)
def test_a_field_needing_a_finite_quantity_refuses_infinity_and_nan(
    text: str, expected: str
) -> None:
    data = load_yaml_text(text, "w.yaml")
    with pytest.raises(WorldError) as info:
        FieldReader("w.yaml", WorldError).quantity(data, "x", "distance")
    assert str(info.value) == f"{expected} (write a finite distance)"


def test_a_field_reader_locates_a_decimal_comma() -> None:
    data = load_yaml_text("a: 1\nspeed: 0,2 m/s\n", "w.yaml")
    with pytest.raises(InputError) as info:
        FieldReader("w.yaml").quantity(data, "speed", "speed")
    assert str(info.value) == (
        "w.yaml:2:8: error: '0,2 m/s' has a decimal comma (use a decimal point: 0.2 m/s)"
    )


MISSION = """\
mission: bare
initial: go
states:
  go:
    do: {drive: {distance: 50, speed: 15 cm/s}}
    timeout: 10
    on: {done: beep, failed: beep, timeout: beep}
  beep:
    do: {play_tone: {frequency: 880 Hz, duration: 200}}
    final: success
"""


def test_a_mission_warns_at_each_bare_number(write_mission: Callable[..., Path]) -> None:
    path = write_mission(MISSION)
    spec, warnings = load_mission(path)
    assert spec.states["go"].action is not None
    assert spec.states["go"].action.kwargs["distance_mm"] == 50.0  # accepted, as before
    assert [w.format() for w in warnings] == [
        (
            f"{path}:5:28: warning: drive distance: 50 taken as 50 mm; write `50 mm`"
            " (or did you mean 50 cm?)"
        ),
        f"{path}:6:14: warning: state 'go': timeout: 10 taken as 10 s; write `10 s`",
        (
            f"{path}:9:51: warning: play_tone duration: 200 taken as 200 s; write `200 s`"
            " (or did you mean 200 ms?)"
        ),
    ]


def test_the_python_twin_writes_units_in_names_and_is_not_warned() -> None:
    # square.py gives Drive(distance_mm=500), Rotate(angle_deg=90): bare numbers, unit named
    _spec, warnings = load_mission(MISSIONS / "square.py")
    assert not [w for w in warnings if "taken as" in w.message]


def run_check(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "roboscript", "check", *args],
        capture_output=True,
        text=True,
        timeout=HANG_BOUND_S,
        check=False,
    )


def test_check_strict_makes_the_warnings_errors(write_mission: Callable[..., Path]) -> None:
    path = write_mission(MISSION)
    relaxed = run_check(str(path))
    assert relaxed.returncode == 0
    assert "warning: drive distance: 50 taken as 50 mm" in relaxed.stderr
    strict = run_check("--strict", str(path))
    assert strict.returncode == 2
    assert f"{path}:5:28: error: drive distance: 50 taken as 50 mm; write `50 mm`" in (
        strict.stderr
    )
    assert "warning:" not in strict.stderr
    assert strict.stderr.splitlines()[-1] == "checked 1 file: 1 with errors"
