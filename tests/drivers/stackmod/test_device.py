"""The simulated StackMod modules, driven through raw packets as real modules would be."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import pytest

from roboscript.drivers.stackmod.codec import braces_excluded_checksum, seed_checksum
from roboscript.drivers.stackmod.device import BATTERY_ADC, StackModRover
from roboscript.errors import ProfileError
from roboscript.profiles import get_profile
from roboscript.sim.geometry import Segment
from roboscript.sim.simulation import Simulation, make_simulation
from roboscript.sim.world import TapeLine, World, load_world


def pk(frame: bytes) -> bytes:
    """``frame`` (from ``{`` to ``}``) with its seed-rule checksum appended."""
    return frame + bytes([seed_checksum(frame)])


class Rover:
    """A simulated rover plus a clock, speaking bytes."""

    def __init__(self, world: World | str = "empty", **options: Any) -> None:
        profile = replace(get_profile("stackmod-rover"), options=options)
        world = load_world(world) if isinstance(world, str) else world
        self.sim = Simulation(world, profile, seed=1)
        self.sim.connect()
        self.now = 0.0

    @property
    def device(self) -> StackModRover:
        device = self.sim.device
        assert isinstance(device, StackModRover)
        return device

    def run(self, seconds: float) -> None:
        end = self.now + seconds
        while self.now < end - 1e-9:
            self.now = round(self.now + 0.01, 6)
            self.sim.tick(self.now, 0.01)

    def send(self, *packets: bytes) -> bytes:
        """Send packets; return every byte the modules answered."""
        for packet in packets:
            self.sim.write(packet)
        return self.sim.read(self.sim.in_waiting)


def test_the_seed_examples_are_answered_byte_for_byte() -> None:
    rover = Rover(motor_address="X", servo_address="X")
    rover.send(pk(b"{X$ARM01}"))
    assert rover.send(b"{X$MTR2+078}" + pk(b"{X$MTR2+078}")[-1:]) == b""
    assert rover.send(b"{X?MTR2}X") == b"{X?MTR2+078}C"
    assert rover.send(b"{X$MTR2+025} ", b"{X?MTR2}X") == pk(b"{X?MTR2+025}")
    rover.send(pk(b"{X$SRV1038}"))
    assert rover.send(b"{X?SRV1}_") == b"{X?SRV1038};"
    assert rover.send(b"{X$SRV1168}$", b"{X?SRV1}_") == pk(b"{X?SRV1168}")


def test_a_plain_seed_mtr_set_moves_the_motor_without_any_arm() -> None:
    """ARM has no data format in the seed: a module built on the seed alone moves its motor on
    the document's own ``{X$MTR2+025}``, so roboscript's simulated modules do too."""
    rover = Rover(motor_address="X")
    assert rover.send(b"{X$MTR2+025} ") == b""  # the seed's example, checksum and all
    assert rover.sim.body.power == [0.0, 0.25]
    rover.send(pk(b"{X$MTR1-050}"))
    assert rover.sim.body.power == [-0.5, 0.25]
    assert rover.send(pk(b"{X?ARM0}")) == pk(b"{X?ARM01}")


def test_a_disarmed_module_ignores_outputs_and_says_why_once(
    caplog: pytest.LogCaptureFixture,
) -> None:
    rover = Rover()
    rover.send(pk(b"{M$ARM00}"))
    with caplog.at_level("WARNING", logger="roboscript.drivers.stackmod.device"):
        rover.send(pk(b"{M$MTR1+050}"), pk(b"{M$MTR2+050}"))
    assert rover.sim.body.power == [0.0, 0.0]
    assert rover.send(pk(b"{M?MTR1}")) == pk(b"{M?MTR1+000}")
    said = (
        "simulated StackMod module 'M' (0x4D) ignores MTR SETs: a host disarmed it with ARM 0 "
        "(send ARM 1 to arm it again)"
    )
    assert [r.getMessage() for r in caplog.records] == [said]
    rover.send(pk(b"{M$ARM01}"), pk(b"{M$MTR1+050}"), pk(b"{M$MTR2-030}"))
    assert rover.sim.body.power == [0.5, -0.3]
    assert rover.send(pk(b"{M?ARM0}")) == pk(b"{M?ARM01}")


def test_disarming_the_motor_module_stops_the_wheels() -> None:
    rover = Rover()
    rover.send(pk(b"{M$ARM01}"), pk(b"{M$MTR1+050}"), pk(b"{M$MTR2+050}"))
    rover.run(0.5)
    assert rover.sim.body.wheel_speed_mm_s[0] > 100.0
    rover.send(pk(b"{M$ARM00}"))
    assert rover.sim.body.power == [0.0, 0.0]
    assert rover.send(pk(b"{M?MTR2}")) == pk(b"{M?MTR2+000}")


def test_motor_numbers_and_inversion_follow_the_wiring_options() -> None:
    rover = Rover(left_motor=3, right_motor=4, invert_right=True)
    rover.send(pk(b"{M$ARM01}"), pk(b"{M$MTR3+040}"), pk(b"{M$MTR4-040}"), pk(b"{M$MTR1+099}"))
    assert rover.sim.body.power == [0.4, 0.4]
    assert rover.send(pk(b"{M?MTR1}")) == b""


def test_a_driven_rover_moves_forward() -> None:
    rover = Rover()
    rover.send(pk(b"{M$ARM01}"), pk(b"{M$MTR1+025}"), pk(b"{M$MTR2+025}"))
    rover.run(2.0)
    assert 180.0 < rover.sim.body.y_mm < 200.0
    assert abs(rover.sim.body.x_mm) < 5.0


def test_ultrasonic_answers_whole_centimetres_or_no_echo() -> None:
    # The room's north wall is 1 m from the centre; the sensor sits 90 mm ahead of it.
    answer = Rover("square-room").send(pk(b"{U?ULT0}"))
    assert answer[:7] == b"{U?ULT0" and answer[-1:] == pk(answer[:-1])[-1:]
    assert 85 <= int(answer[7:10]) <= 95
    assert Rover("empty").send(pk(b"{U?ULT0}")) == pk(b"{U?ULT0999}")


def test_ultrasonic_sensor_1_faces_right() -> None:
    # Corridor: the right wall is 400 mm from the start, minus the body's half width.
    rover = Rover("corridor")
    expected = round(rover.sim.body.side_range_mm() or 0.0) // 10
    answer = rover.send(pk(b"{U?ULT1}"))
    assert answer[:7] == b"{U?ULT1"
    assert abs(int(answer[7:10]) - expected) <= 1
    assert rover.send(pk(b"{U?ULT2}")) == b""


def test_ir_sensors_answer_the_line_readings_left_to_right() -> None:
    # Tape under the left sensor only (the sensors are 80 mm ahead, 15 mm apart).
    tape = TapeLine((Segment(-15.0, 0.0, -15.0, 200.0),), width_mm=10.0)
    rover = Rover(World("tape", lines=(tape,)))
    readings = []
    for sensor in (b"0", b"1", b"2"):
        answer = rover.send(pk(b"{I?IRS" + sensor + b"}"))
        assert answer[:7] == b"{I?IRS" + sensor
        readings.append(int(answer[7:11]))
    assert readings[0] > 700 and readings[1] < 200 and readings[2] < 200


def test_bump_switches_read_1_while_pressed_on_their_digital_pins() -> None:
    rover = Rover()
    body = rover.sim.body
    body.in_contact, body.contact_side = True, "left"
    assert rover.send(pk(b"{I?DGT02}"), pk(b"{I?DGT03}")) == pk(b"{I?DGT021}") + pk(b"{I?DGT030}")
    body.in_contact, body.contact_side = False, None
    assert rover.send(pk(b"{I?DGT02}")) == pk(b"{I?DGT020}")


def test_the_buzzer_pin_sounds_one_pitch_logged_when_it_stops() -> None:
    rover = Rover()
    rover.send(pk(b"{I$ARM01}"))
    rover.run(1.0)
    rover.send(pk(b"{I$DGT081}"))
    assert rover.send(pk(b"{I?DGT08}")) == pk(b"{I?DGT081}")
    rover.run(0.25)
    assert rover.sim.log.tones == []
    rover.send(pk(b"{I$DGT080}"))
    assert rover.sim.log.tones == [(1.0, 2300.0, 0.25)]


def test_digital_outputs_latch_and_inputs_ignore_writes() -> None:
    rover = Rover()
    rover.send(pk(b"{S$ARM01}"), pk(b"{S$DGT131}"), pk(b"{I$ARM01}"), pk(b"{I$DGT021}"))
    assert rover.send(pk(b"{S?DGT13}"), pk(b"{S?DGT12}")) == pk(b"{S?DGT131}") + pk(b"{S?DGT120}")
    assert rover.send(pk(b"{I?DGT02}")) == pk(b"{I?DGT020}")


def test_analog_channel_0_reads_the_battery_on_every_module() -> None:
    rover = Rover()
    battery = f"{BATTERY_ADC:04d}".encode()
    assert rover.send(pk(b"{U?ANL0}")) == pk(b"{U?ANL0" + battery + b"}")
    assert rover.send(pk(b"{M?ANL1}")) == pk(b"{M?ANL10000}")


def test_bad_checksums_and_garbage_are_dropped_silently() -> None:
    rover = Rover()
    assert pk(b"{M?ARM0}")[-1:] != b"!"
    assert rover.send(b"\x00\xffnoise", b"{M?ARM0}!", b"{M?ARM") == b""
    assert rover.send(b"0}" + pk(b"{M?ARM0}")[-1:]) == pk(b"{M?ARM01}")
    faults = rover.device.codec.stats.faults
    assert faults["bad_checksum"] == 1
    assert faults["garbage"] == 1


def test_nobody_answers_a_missing_module_command_or_selector() -> None:
    rover = Rover()
    assert rover.send(pk(b"{Z?ARM0}")) == b""  # no module at Z
    assert rover.send(pk(b"{M?ULT0}")) == b""  # the motor module has no ranger
    assert rover.send(pk(b"{U?ULT2}")) == b""  # two rangers only
    assert rover.send(pk(b"{S?SRV2}")) == b""  # one servo only
    assert rover.send(pk(b"{M?ARM1}")) == b""  # ARM selector 0 is the whole module


def test_sets_are_never_answered() -> None:
    rover = Rover()
    assert rover.send(pk(b"{M$ARM01}"), pk(b"{M$MTR1+010}"), pk(b"{S$SRV1045}")) == b""


def test_braces_excluded_checksum_rule_is_an_option() -> None:
    def excluded(frame: bytes) -> bytes:
        return frame + bytes([braces_excluded_checksum(frame)])

    rover = Rover(checksum="braces_excluded")
    assert rover.send(pk(b"{M?ARM0}")) == b""
    assert rover.send(excluded(b"{M?ARM0}")) == excluded(b"{M?ARM01}")


def test_power_loss_stops_everything_and_modules_come_back_as_at_power_on() -> None:
    rover = Rover()
    rover.send(pk(b"{M$ARM01}"), pk(b"{M$MTR1+050}"), pk(b"{I$ARM01}"), pk(b"{I$DGT081}"))
    rover.run(0.1)
    rover.sim.stop_all()
    assert rover.sim.body.power == [0.0, 0.0]
    assert [round(d, 3) for _, _, d in rover.sim.log.tones] == [0.1]
    assert rover.send(pk(b"{M?MTR1}"), pk(b"{M?ARM0}")) == pk(b"{M?MTR1+000}") + pk(b"{M?ARM01}")


def test_the_built_in_robot_has_a_simulator() -> None:
    sim = make_simulation("stackmod-rover")
    assert isinstance(sim.device, StackModRover)
    assert sim.device.options.motor_address == ord("M")


def test_a_bad_option_fails_before_the_simulation_starts() -> None:
    profile = replace(get_profile("stackmod-rover"), options={"motor_address": "m"})
    with pytest.raises(ProfileError, match="motor_address"):
        Simulation(load_world("empty"), profile)
