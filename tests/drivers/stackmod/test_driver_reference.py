"""The StackMod driver speaking the author's firmware (``stackmod-reference``), on its twin."""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import pytest

from roboscript import capabilities as cap
from roboscript.drivers.stackmod.driver import StackModDriver
from roboscript.drivers.stackmod.reference_device import LOOP_PERIOD_S, ReferenceModule
from roboscript.errors import ProfileError
from roboscript.profiles import get_profile
from roboscript.robot import Robot
from roboscript.transport.wirelog import read_wire_log

_WRITE = re.compile(rb"2\{Ep\$MTR([12])([+-]\d{3})\}(.)", re.DOTALL)
"""One write of the driver: register byte, the 11 characters, the checksum."""


def writes(log: Path) -> list[bytes]:
    return [data for _, direction, data in read_wire_log(log) if direction == ">"]


def module_of(bot: Robot) -> ReferenceModule:
    assert bot.simulation is not None
    device = bot.simulation.device
    assert isinstance(device, ReferenceModule)
    return device


def test_the_robot_is_ready_at_once_with_a_drive_base_only() -> None:
    with Robot.connect("stackmod-reference") as bot:
        assert bot.driver.ready_s == bot.driver.connected_s  # nothing to wait for
        assert set(bot.capabilities) == {cap.DRIVE_BASE}
        assert any("answers nothing" in notice for notice in bot.driver.notices)
        assert "answers nothing" in bot.describe()


def test_every_write_is_one_mtr_set_with_the_register_byte_and_no_get(tmp_path: Path) -> None:
    log = tmp_path / "wire.log"
    with Robot.connect("stackmod-reference", wire_log=str(log)) as bot:
        bot.drive_base.set_wheel_speeds(150.0, -150.0)
        bot.run_for(1.0)
        bot.drive_base.set_wheel_speeds(80.0, 80.0)
        bot.run_for(1.0)
        taken = module_of(bot).taken
    sent = writes(log)
    assert len(sent) >= 6
    for data in sent:
        match = _WRITE.fullmatch(data)
        assert match is not None, data
        text = data[2:13]
        assert match.group(3)[0] == sum(b - 32 for b in text) % 95 + 32
    assert taken == len(sent) - 2  # all but the two stops sent on the way out, read later


def test_speeds_become_pwm_up_to_255_and_the_wheels_turn_at_that_speed(tmp_path: Path) -> None:
    log = tmp_path / "wire.log"
    with Robot.connect("stackmod-reference", wire_log=str(log)) as bot:
        driver = bot.driver
        assert isinstance(driver, StackModDriver)
        # Past full power on the left (the drive base itself stops at the profile's 300 mm/s).
        driver.set_wheel_speeds(1000.0, 200.0)
        bot.run_for(2.0)
        assert bot.simulation is not None
        speeds = list(bot.simulation.body.wheel_speed_mm_s)
    first = [_WRITE.fullmatch(data) for data in writes(log)[2:4]]  # after the opening stops
    pwm = [int(match.group(2)) for match in first if match is not None]
    assert pwm[0] == 255
    assert 120 < pwm[1] < 135  # 200 mm/s is about half the 400 mm/s of PWM 255
    assert speeds == pytest.approx([400.0, 200.0], rel=0.05)


def test_distances_are_estimated_open_loop_from_the_calibration() -> None:
    with Robot.connect("stackmod-reference") as bot:
        bot.drive_base.set_wheel_speeds(200.0, 200.0)
        bot.run_for(3.0)
        estimated = bot.drive_base.wheel_distances_mm()
        assert bot.simulation is not None
        travelled = bot.simulation.body.y_mm
    # Commanded speed times time; the robot lags it by the firmware's 200 ms loop and the
    # motors' spin-up, which an open-loop estimate cannot see.
    assert estimated[0] == pytest.approx(600.0, abs=10.0)
    assert estimated[0] - 200.0 * (LOOP_PERIOD_S + 0.1) < travelled < estimated[0]


def test_leaving_sends_mtr_zero_to_both_motors_and_the_loop_applies_it(tmp_path: Path) -> None:
    log = tmp_path / "wire.log"
    with pytest.raises(RuntimeError), Robot.connect("stackmod-reference", wire_log=str(log)) as bot:
        bot.drive_base.set_wheel_speeds(150.0, 150.0)
        bot.run_for(0.5)
        raise RuntimeError("student code crashed")
    assert writes(log)[-2:] == [b"2{Ep$MTR1+000}[", b"2{Ep$MTR2+000}\\"]
    sim = bot.simulation
    assert sim is not None
    sim.tick(sim.time_s + LOOP_PERIOD_S, LOOP_PERIOD_S)
    assert sim.body.power == [0.0, 0.0]


def test_a_profile_listing_sensors_on_the_reference_firmware_is_refused() -> None:
    rover = get_profile("stackmod-rover")
    profile = replace(rover, name="my-rover", options=get_profile("stackmod-reference").options)
    with pytest.raises(ProfileError, match=r"my-rover: .* cannot offer bumper, line, range"):
        Robot.connect(profile)
