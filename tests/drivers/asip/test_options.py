"""ASIP profile options: the sketch's servos, pixels and LCD width, checked when read."""

from __future__ import annotations

from pathlib import Path

import pytest

from roboscript.drivers.asip.options import AsipOptions
from roboscript.errors import ProfileError
from roboscript.profiles import get_profile
from roboscript.sim.simulation import make_simulation


def test_the_mirto_profile_is_the_mirtle2017_sketch() -> None:
    options = AsipOptions.from_mapping(get_profile("mirto").options, profile="mirto")
    assert (options.servo_count, options.pixel_count, options.lcd_columns) == (1, 9, 20)


@pytest.mark.parametrize(
    ("transport", "int_bits"), [("usb", 32), ("uart", 16)], ids=["teensy", "atmega328p"]
)
def test_the_boards_int_width_follows_its_transport(transport: str, int_bits: int) -> None:
    options = AsipOptions.from_mapping({"transport": transport}, profile="x")
    assert options.int_bits == int_bits


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"servo_count": -1}, "'servo_count' must be a whole number 0-16"),
        ({"lcd_columns": 21}, "'lcd_columns' must be a whole number 1-20"),
        ({"pixel_count": True}, "'pixel_count' must be a whole number 0-1024"),
        ({"reset_on_connect": "yes"}, "'reset_on_connect' must be true or false"),
        ({"reset_on_connect": 1}, "'reset_on_connect' must be true or false"),
    ],
)
def test_a_bad_value_names_the_option_and_its_range(
    options: dict[str, object], message: str
) -> None:
    with pytest.raises(ProfileError, match=message):
        AsipOptions.from_mapping(options, profile="x")


def test_an_unknown_option_suggests_the_close_one() -> None:
    with pytest.raises(ProfileError) as caught:
        AsipOptions.from_mapping({"servos_count": 2}, profile="x")
    assert caught.value.hint == "did you mean 'servo_count'?"


def test_a_profile_file_builds_a_board_with_its_servos_and_pixels(tmp_path: Path) -> None:
    path = tmp_path / "mirto-two.yaml"
    path.write_text("extends: mirto\noptions:\n  servo_count: 2\n  pixel_count: 4\n")
    profile = get_profile(str(path))
    assert profile.options == {"servo_count": 2, "pixel_count": 4, "lcd_columns": 20}
    sim = make_simulation(str(path), "empty", seed=1)
    sim.connect()
    sim.read(sim.in_waiting)
    sim.write(b"P,I,0\nS,W,1,30\n")
    assert sim.read(sim.in_waiting) == b"@P,I,0,4\n"
    assert sim.device.state.servos_deg == [90, 30]  # type: ignore[attr-defined]


def test_a_board_that_resets_on_connect_is_built_from_the_option() -> None:
    assert AsipOptions.from_mapping({}, profile="mirto").reset_on_connect is False
    options = AsipOptions.from_mapping({"reset_on_connect": True}, profile="mirto")
    assert options.reset_on_connect is True
    simulation = make_simulation("mirto", options={"reset_on_connect": True})
    simulation.connect()
    assert simulation.in_waiting == 0  # starting again: no greeting yet
    simulation.tick(3.3, 3.3)
    assert simulation.in_waiting == 0  # the Uno's bootloader waited 1.37 s first
    simulation.tick(4.7, 1.4)
    assert simulation.read(simulation.in_waiting).startswith(b"!Mirtle2017 running on")
