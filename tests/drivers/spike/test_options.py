"""SPIKE profile options: ports by letter, checked values, and a profile file that uses them."""

from __future__ import annotations

from pathlib import Path

import pytest

from roboscript.drivers.spike.options import SpikeOptions
from roboscript.errors import ProfileError
from roboscript.profiles import get_profile
from roboscript.robot import Robot


def test_defaults_follow_a_lego_driving_base() -> None:
    options = SpikeOptions.from_mapping({}, profile="spike-prime")
    assert options.ports == {
        "left_motor": 0,
        "right_motor": 1,
        "force": 2,
        "distance": 3,
        "color": 4,
    }
    assert (options.agent_slot, options.telemetry_ms) == (19, 50)


def test_ports_are_letters_in_either_case() -> None:
    options = SpikeOptions.from_mapping({"left_motor": "e", "right_motor": "F"}, profile="p")
    assert (options.left_motor, options.right_motor) == (4, 5)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"left_motor": "G"}, "option 'left_motor' must be a port letter A-F, got 'G'"),
        ({"distance": 3}, "option 'distance' must be a port letter A-F, got 3"),
        ({"agent_slot": 20}, "option 'agent_slot' must be a whole number 0-19, got 20"),
        ({"telemetry_ms": 5}, "option 'telemetry_ms' must be a whole number 10-1000, got 5"),
        ({"left_motor": "B"}, "left_motor and right_motor must be different ports"),
    ],
)
def test_bad_values_are_refused_naming_the_option(options: dict[str, object], message: str) -> None:
    with pytest.raises(ProfileError) as caught:
        SpikeOptions.from_mapping(options, profile="base-7")
    assert caught.value.message == f"base-7: {message}"


def test_an_unknown_option_gets_a_suggestion() -> None:
    with pytest.raises(ProfileError) as caught:
        SpikeOptions.from_mapping({"left_moter": "A"}, profile="base-7")
    assert caught.value.hint == "did you mean 'left_motor'?"


def test_a_profile_file_rewires_the_driver_and_the_simulated_hub(tmp_path: Path) -> None:
    path = tmp_path / "team4.yaml"
    path.write_text(
        "extends: spike-prime\noptions: {left_motor: E, right_motor: F, agent_slot: 3}\n",
        encoding="utf-8",
    )
    assert get_profile(str(path)).options["left_motor"] == "E"
    with Robot.connect(str(path)) as robot:
        robot.drive_base.set_wheel_speeds(100.0, 100.0)
        robot.run_for(1.0)
        assert robot.drive_base.wheel_distances_mm()[0] > 50
        assert 3 in robot.simulation.device.slots


def test_extra_motors_default_to_the_ports_no_other_option_names() -> None:
    assert SpikeOptions.from_mapping({}, profile="p").motors == (5,)
    rewired = SpikeOptions.from_mapping({"left_motor": "E", "right_motor": "F"}, profile="p")
    assert rewired.motors == (0, 1)  # A and B are free once the wheels move to E and F


@pytest.mark.parametrize(("value", "ports"), [("c", (2,)), (["C"], (2,)), ("", ())])
def test_extra_motors_are_port_letters(value: object, ports: tuple[int, ...]) -> None:
    # With the force sensor moved to F, C is the one port no device option names.
    options = SpikeOptions.from_mapping({"force": "F", "motors": value}, profile="p")
    assert options.motors == ports


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ("G", "option 'motors' must be port letters A-F"),
        (3, "option 'motors' must be port letters A-F"),
        ("FF", "lists a port twice"),
        ("D", "lists port D, which is the distance's port"),
        ("A", "lists port A, which is the left motor's port"),
    ],
)
def test_bad_extra_motor_ports_are_refused(value: object, message: str) -> None:
    with pytest.raises(ProfileError, match=message):
        SpikeOptions.from_mapping({"motors": value}, profile="p")
