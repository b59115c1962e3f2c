"""The simulated module of the StackMod author's firmware, fed raw I2C writes."""

from __future__ import annotations

import pytest

from roboscript.drivers.stackmod.reference_device import (
    LOOP_PERIOD_S,
    ReferenceModule,
    scan_int,
)
from roboscript.sim.simulation import Simulation, make_simulation


def ref(text: bytes) -> bytes:
    """``{text}`` and the author's checksum: the sum over ``text`` only, braces left out."""
    return b"{" + text + b"}" + bytes([sum(b - 32 for b in text) % 95 + 32])


class Module:
    """The author's module on a simulated body, with a clock."""

    def __init__(self) -> None:
        self.sim: Simulation = make_simulation("stackmod-reference")
        self.sim.connect()
        self.now_s = 0.0

    @property
    def device(self) -> ReferenceModule:
        device = self.sim.device
        assert isinstance(device, ReferenceModule)
        return device

    @property
    def registers(self) -> list[int]:
        return self.device.motor_registers[:3]

    def write(self, *writes: bytes) -> bytes:
        """Each argument is one I2C write; return whatever the module sent back."""
        for data in writes:
            self.sim.write(data)
        return self.sim.read(1024)

    def run(self, seconds: float) -> None:
        end = self.now_s + seconds
        while self.now_s < end - 1e-9:
            self.now_s = round(self.now_s + 0.005, 6)
            self.sim.tick(self.now_s, 0.005)


def test_the_authors_client_packet_sets_motor_1() -> None:
    module = Module()
    assert ref(b"Mp$MTR1+139") == b"{Mp$MTR1+139}p"
    assert module.write(b"2{Mp$MTR1+139}p") == b""
    assert module.registers == [139, 0, 0]
    module.run(LOOP_PERIOD_S)
    assert module.sim.body.power == pytest.approx([139 / 255, 0.0])


def test_motors_move_only_when_the_main_loop_next_runs() -> None:
    module = Module()
    module.run(0.01)  # the loop ran at power-on; the next run is at 0.2 s
    module.write(b"2" + ref(b"Ep$MTR1-255"), b"2" + ref(b"Ep$MTR2+051"))
    module.run(0.18)
    assert module.sim.body.power == [0.0, 0.0]
    module.run(0.02)
    assert module.sim.body.power == pytest.approx([-1.0, 0.2])


def test_the_seed_checksum_rule_is_dropped() -> None:
    module = Module()
    module.write(b"2{Mp$MTR1+139}j")  # 'j' sums the braces too, as the seed document does
    assert module.registers == [0, 0, 0]
    assert module.device.bad_checksums == 1


def test_a_packet_split_over_two_writes_is_lost() -> None:
    module = Module()
    packet = b"2" + ref(b"Ep$MTR1+100")
    module.write(packet[:8], packet[8:])
    module.write(packet[:-2], packet[-2:])  # even when only the '}' and checksum are late
    assert module.registers == [0, 0, 0]
    module.write(packet)
    assert module.registers == [100, 0, 0]


def test_packets_after_the_32nd_byte_of_a_write_are_lost() -> None:
    module = Module()
    one, two, three = ref(b"Ep$MTR1+010"), ref(b"Ep$MTR2+020"), ref(b"Ep$MTR3+030")
    module.write(b"2" + one + two + three)  # 43 bytes: the third packet is cut at byte 32
    assert module.registers == [10, 20, 0]


@pytest.mark.parametrize(
    ("text", "reason"),
    [
        (b"E$MTR1+100", "unknown"),  # the seed's one-address form: "TR1" where MTR should be
        (b"Ep$MTR1+0100", "MTR SET of 12 characters, not 11"),
        (b"Ep?MTR1", "MTR without '$' (the firmware answers no GET)"),
        (b"Ep?MTR1+100", "MTR without '$' (the firmware answers no GET)"),  # 11, but a GET
        (b"Ep$SRV1090", "a command the firmware does not act on"),
        (b"Ep$XYZ1+100", "unknown"),
        (b"Ep$MTR0+100", "motor 0 (the firmware has motors 1-15)"),
        (b"Ep$MTR10255", "MTR data that sscanf cannot read as two numbers"),
        (b"Ep$M", "shorter than 5 characters"),
    ],
)
def test_only_an_11_character_mtr_set_of_motors_1_to_15_does_anything(
    text: bytes, reason: str
) -> None:
    module = Module()
    assert module.write(b"2" + ref(text)) == b""
    assert module.device.motor_registers == [0] * 15
    assert module.device.taken == 0
    assert dict(module.device.ignored) == {reason: 1}


@pytest.mark.parametrize(
    ("text", "registers"),
    [
        (b"Ep$MTR1 -50", [-50, 0, 0]),  # spaces before a number are skipped
        (b"Ep$MTR3+1x9", [0, 0, 1]),  # the number ends at the first non-digit
        (b"Ep$MTR+2-07", [0, -7, 0]),  # a signed motor number is still a number
        (b"Zz$MTR1+050", [50, 0, 0]),  # the address bytes are not checked
        (b"@@$MTR2+999", [0, 999, 0]),  # nor is the value range
    ],
)
def test_the_motor_and_value_are_read_as_sscanf_reads_them(
    text: bytes, registers: list[int]
) -> None:
    module = Module()
    module.write(b"2" + ref(text))
    assert module.registers == registers


def test_two_digit_motors_are_stored_but_drive_nothing() -> None:
    module = Module()
    module.write(b"2" + ref(b"Ep$MTR12+34"))
    module.run(LOOP_PERIOD_S)
    assert module.device.motor_registers[11] == 34
    assert module.sim.body.power == [0.0, 0.0]


def test_a_brace_inside_a_packet_restarts_it_without_rewinding() -> None:
    module = Module()
    # The firmware clears its text on the second '{' but keeps writing after "Ep", so the
    # text reads as empty and the checksum of the whole packet no longer matches.
    module.write(b"2{Ep" + ref(b"Ep$MTR1+050"))
    assert module.registers == [0, 0, 0]
    assert module.device.bad_checksums == 1
    # The empty text's checksum is 32, a space: then the firmware reads an empty packet.
    module.write(b"2{Ep{Ep$MTR1+050} ")
    assert module.device.bad_checksums == 1
    assert dict(module.device.ignored) == {"shorter than 5 characters": 1}


def test_a_nul_byte_resets_the_parser() -> None:
    module = Module()
    packet = ref(b"Ep$MTR1+050")
    module.write(packet[:6] + b"\0" + packet[6:])
    assert module.registers == [0, 0, 0]
    module.write(b"\0" + packet)
    assert module.registers == [50, 0, 0]


def test_the_byte_after_the_closing_brace_is_the_checksum_whatever_it_is() -> None:
    candidates = (
        bytes([a]) + b"p$MTR1+%03d" % pwm for a in range(0x40, 0x60) for pwm in range(256)
    )
    text = next(t for t in candidates if ref(t)[-1:] == b"{")
    module = Module()
    module.write(ref(text) + ref(b"Ep$MTR2+077"))
    assert module.registers[1] == 77
    assert module.registers[0] == int(text[-3:])


def test_bytes_above_0x7f_count_negative_in_the_checksum() -> None:
    """AVR's ``char`` is signed: 0xC5 adds 0xC5 - 256 - 32 = -91 to the sum."""
    text = b"\xc5p$MTR1+050"
    total = (0xC5 - 256 - 32) + sum(b - 32 for b in text[1:])
    assert total > 0  # so C's % and Python's agree here
    module = Module()
    module.write(b"{" + text + b"}" + bytes([total % 95 + 32]))
    assert module.registers == [50, 0, 0]


def test_a_negative_sum_never_matches_a_checksum_byte() -> None:
    """Two 0x80 bytes make the sum -88; C's % gives -88 % 95 = -88, so the firmware's checksum
    is -56, which no byte equals (Python's % would give 7, a quote character)."""
    text = b"\x80\x80$MTR1+050"
    total = 2 * (0x80 - 256 - 32) + sum(b - 32 for b in text[2:])
    assert total == -88
    module = Module()
    # Neither Python's -88 % 95 + 32 (a quote) nor |-88| % 95 + 32 ('x') is the firmware's.
    module.write(b"{" + text + b"}'", b"{" + text + b"}x")
    assert module.registers == [0, 0, 0]
    assert module.device.bad_checksums == 2


def test_values_past_255_drive_at_full_power() -> None:
    module = Module()
    module.write(ref(b"Ep$MTR1-999"), ref(b"Ep$MTR2+256"))
    module.run(LOOP_PERIOD_S)
    assert module.sim.body.power == [-1.0, 1.0]


def test_nothing_is_ever_sent_back() -> None:
    module = Module()
    assert module.write(b"2" + ref(b"Ep?MTR1"), b"2" + ref(b"Ep?ARM0")) == b""
    module.run(1.0)
    assert module.sim.read(1024) == b""


def test_power_loss_clears_the_registers_and_stops_the_wheels() -> None:
    module = Module()
    module.write(b"2" + ref(b"Ep$MTR1+200"), b"2" + ref(b"Ep$MTR2+200"))
    module.run(0.5)
    assert module.sim.body.wheel_speed_mm_s[0] > 100.0
    module.sim.stop_all()
    assert module.sim.body.power == [0.0, 0.0]
    assert module.registers == [0, 0, 0]


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (b"  +12x", (12, 5)),
        (b"-0", (0, 2)),
        (b"+", None),
        (b"x1", None),
        (b"", None),
    ],
)
def test_scan_int_reads_one_c_integer(text: bytes, expected: tuple[int, int] | None) -> None:
    assert scan_int(text, 0) == expected
