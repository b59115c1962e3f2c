"""StackMod profile options: defaults, profile files, and errors that name the option."""

from __future__ import annotations

from pathlib import Path

import pytest

from roboscript.drivers.stackmod.options import StackModOptions, address_name
from roboscript.errors import ProfileError
from roboscript.profiles import get_profile


def read(**options: object) -> StackModOptions:
    return StackModOptions.from_mapping(options, profile="rover-7")


def test_the_built_in_rover_uses_the_defaults() -> None:
    profile = get_profile("stackmod-rover")
    assert profile.protocol == "stackmod"
    assert profile.baudrate == 9600
    options = StackModOptions.from_mapping(profile.options, profile=profile.name)
    assert options == StackModOptions()
    assert options.module_roles == {
        ord("M"): ("motor",),
        ord("S"): ("servo",),
        ord("U"): ("ultrasonic",),
        ord("I"): ("IR", "IO"),
    }


def test_addresses_are_written_as_characters_or_numbers() -> None:
    options = read(motor_address="X", servo_address=0x58, ir_address="@", io_address="_")
    assert (options.motor_address, options.servo_address) == (0x58, 0x58)
    assert (options.ir_address, options.io_address) == (0x40, 0x5F)
    assert options.describe_module(0x58) == "the motor/servo module at 'X' (0x58)"
    assert address_name(0x4D) == "'M' (0x4D)"


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"motor_address": "m"}, "option 'motor_address' must be one character from '@' to '_'"),
        ({"motor_address": "MM"}, "option 'motor_address' must be one character"),
        ({"ultrasonic_address": 0x60}, "option 'ultrasonic_address' must be one character"),
        ({"checksum": "crc"}, "option 'checksum' must be 'seed' or 'braces_excluded'"),
        ({"firmware": "v2"}, "option 'firmware' must be 'seed' or 'reference'"),
        ({"framing": "spi"}, "option 'framing' must be 'serial' or 'i2c'"),
        (
            {"firmware": "reference"},
            "the reference firmware sums its checksum without the braces",
        ),
        (
            {"firmware": "reference", "checksum": "braces_excluded", "left_motor": 0},
            "the reference firmware numbers its motors from 1",
        ),
        ({"invert_left": "yes"}, "option 'invert_left' must be true or false"),
        ({"left_motor": 10}, "option 'left_motor' must be a whole number 0-9"),
        ({"left_motor": 2}, "left_motor and right_motor must differ"),
        ({"bumper_pins": [2]}, "option 'bumper_pins' must be two pin numbers 0-99"),
        ({"bumper_pins": [2, 8]}, "bumper_pins and buzzer_pin must be different pins"),
        ({"min_power_pct": 0}, "option 'min_power_pct' must be a whole number 1-100"),
        ({"get_retries": True}, "option 'get_retries' must be a whole number 0-10"),
        ({"get_timeout_s": 0}, "option 'get_timeout_s' must be a positive number"),
        (
            {"wheel_speed_mm_s_per_pct": "fast"},
            "option 'wheel_speed_mm_s_per_pct' must be a positive",
        ),
    ],
)
def test_bad_values_name_the_profile_and_option(options: dict[str, object], message: str) -> None:
    with pytest.raises(ProfileError) as raised:
        StackModOptions.from_mapping(options, profile="rover-7")
    assert f"rover-7: {message}" in str(raised.value)


def test_an_unknown_option_gets_a_suggestion() -> None:
    with pytest.raises(ProfileError) as raised:
        read(motor_adress="X")
    assert raised.value.hint == "did you mean 'motor_address'?"


def test_a_profile_file_changes_only_the_options_it_names(tmp_path: Path) -> None:
    path = tmp_path / "rover-7.yaml"
    path.write_text(
        "extends: stackmod-rover\n"
        "options:\n"
        "  motor_address: X\n"
        "  bumper_pins: [4, 5]\n"
        "  wheel_speed_mm_s_per_pct: 2.6\n",
        encoding="utf-8",
    )
    profile = get_profile(str(path))
    assert profile.name == "rover-7"
    options = StackModOptions.from_mapping(profile.options, profile=profile.name)
    assert options.motor_address == ord("X")
    assert options.bumper_pins == (4, 5)
    assert options.wheel_speed_mm_s_per_pct == 2.6
    assert options.servo_address == ord("S")


def test_options_must_be_a_mapping_in_a_profile_file(tmp_path: Path) -> None:
    path = tmp_path / "rover.yaml"
    path.write_text("extends: stackmod-rover\noptions: [motor_address]\n", encoding="utf-8")
    with pytest.raises(ProfileError, match=r"rover\.yaml:2:1: error: 'options' maps"):
        get_profile(str(path))


def test_the_reference_profile_speaks_the_authors_firmware() -> None:
    profile = get_profile("stackmod-reference")
    options = StackModOptions.from_mapping(profile.options, profile=profile.name)
    assert (options.firmware, options.checksum, options.framing) == (
        "reference",
        "braces_excluded",
        "i2c",
    )
    assert options.motor_address == ord("E")  # the author's module, I2C slave 0x45
    assert (options.left_motor, options.right_motor) == (1, 2)
    assert not options.answers_get
    assert options.module_roles == {ord("E"): ("motor",)}
    assert StackModOptions().answers_get


def test_a_profile_file_can_extend_the_reference_profile(tmp_path: Path) -> None:
    path = tmp_path / "modbot.yaml"
    path.write_text(
        "extends: stackmod-reference\noptions:\n  wheel_speed_mm_s_per_pct: 2.0\n",
        encoding="utf-8",
    )
    profile = get_profile(str(path))
    options = StackModOptions.from_mapping(profile.options, profile=profile.name)
    assert options.firmware == "reference"
    assert options.wheel_speed_mm_s_per_pct == 2.0
