"""roboscript's simulated PLEN2 against PLEN2's own firmware.

The firmware (``plen-Firmware_Arduino`` 1.4.2) runs unchanged on an emulated ATmega32u4 at
16 MHz. It answers on USB serial, which the emulator lacks, so its replies are sent to UART1
(2 Mbaud) instead (one forced ``#define``, ``shims/plen2/replies_on_uart1.h``), the line it
reads commands from. Each probe (``plen2_probes.py``) goes to it and to ``roboscript sim``'s
PLEN2 (``transport: uart``, the same line) on one connection, in turn;
what each answers is compared byte for byte, and so are the 24 servo outputs each drives
afterwards (the firmware's ``JointController::m_pwms``; the simulated board's joint angles
through the firmware's own ``map()``). Differences are listed in ``KNOWN_DIFFERENCES``, each
with the firmware line that decides it (docs/robots/plen2.md lists them too); a listed
difference that goes away fails its test, so the list stays true.

Motions live in the board's external I2C EEPROM (a 24FC1025), attached here as the harness's
own model of the part, erased as delivered; installing, reading back and playing the driver's
gaits against the firmware is ``test_plen2_motions.py``.
"""

from __future__ import annotations

import dataclasses
import struct
from dataclasses import dataclass

import pytest
from firmware.avr import Board, build, symbol_address
from firmware.plen2_lockstep import PWMS, servo_pwm
from firmware.plen2_probes import PROBES, Probe, timed_frame
from firmware.recipes import PLEN2_BAUD, PLEN2_EEPROM, PLEN2_F_CPU_HZ, PLEN2_MCU, plen2_32u4

from roboscript.drivers.plen import messages as m
from roboscript.drivers.plen.device import Plen2Board
from roboscript.drivers.plen.driver import CHUNK_GAP_S
from roboscript.profiles import get_profile
from roboscript.sim.simulation import Simulation
from roboscript.sim.world import load_world

BOOT_S = 0.5
"""``setup()``: serial, the internal EEPROM's joint settings (written at first start), Timer 1."""

PROBE_STEP_S = 0.001
"""The simulator's step in this comparison: every probe's writes and waits are whole
milliseconds, so the simulated board receives each write when the emulated one does (at the
default 5 ms step a write 1 ms after another would reach it at the same instant)."""

KNOWN_DIFFERENCES: dict[str, str] = {}
"""Probes on which the simulated PLEN2 answers otherwise, and the firmware line that decides
each. None is left in the probe set; the one difference kept is
:data:`ERASED_SLOT_DIFFERENCE`, checked on a board of its own below."""

ERASED_SLOT_DIFFERENCE = (
    "MotionController::dump prints an erased slot as Header::get reads it (slot 255, a name of "
    "twenty 0xFF bytes, a loop and a jump code) and then loops to its frame_length, 255 frames "
    "(Frame::get refuses an index of 20 or more and leaves the last frame in place): about "
    "260 KB, 4.5 s of output. The simulated PLEN2 dumps a slot never written as a motion of no "
    "frames, which the driver reads as an erased slot just the same"
)


@dataclass(frozen=True)
class Answer:
    """What one board sent in answer to a probe, and its servo outputs afterwards."""

    sent: bytes
    pwms: tuple[int, ...]


@pytest.fixture(scope="module")
def transcripts() -> tuple[Answer, Answer, list[tuple[Answer, Answer]]]:
    plen2 = get_profile("plen2")
    # the emulated board's host line is its 2 Mbaud UART: the simulated board's `uart`
    profile = dataclasses.replace(plen2, options={**plen2.options, "transport": "uart"})
    # a step that divides every probe's times: a write reaches both boards at one instant
    simulation = Simulation(load_world("empty"), profile, seed=1, physics_dt_s=PROBE_STEP_S)
    simulation.connect()
    device = simulation.device
    assert isinstance(device, Plen2Board)

    def sim_pwms() -> tuple[int, ...]:
        return tuple(servo_pwm(angle) for angle in device.angles_ddeg)

    elf = build(plen2_32u4())
    pwms = symbol_address(elf, PWMS)
    with Board(
        elf, PLEN2_MCU, PLEN2_F_CPU_HZ, uart="1", baud=PLEN2_BAUD, eeprom=PLEN2_EEPROM
    ) as board:

        def firmware_pwms() -> tuple[int, ...]:
            return struct.unpack(f"<{m.JOINT_COUNT}H", board.peek(pwms, 2 * m.JOINT_COUNT))

        greeting_fw = Answer(board.advance_to(BOOT_S), firmware_pwms())
        simulation.tick(BOOT_S, BOOT_S)
        greeting_sim = Answer(simulation.read(simulation.in_waiting), sim_pwms())
        results = []
        for probe in PROBES:
            firmware = bytearray()
            sim = bytearray()
            if probe.idle_s:
                firmware += board.advance(probe.idle_s)
                simulation.tick(board.time_s, probe.idle_s)
                sim += simulation.read(simulation.in_waiting)
            for index, data in enumerate(probe.writes):
                firmware += board.exchange(data, probe.gap_s)
                simulation.write(data)
                simulation.tick(board.time_s, probe.gap_s)
                sim += simulation.read(simulation.in_waiting)
                if probe.reset_after == index + 1:
                    board.reset()
                    device.reset(board.time_s)
            firmware += board.advance(probe.settle_s)
            simulation.tick(board.time_s, probe.settle_s)
            sim += simulation.read(simulation.in_waiting)
            results.append(
                (Answer(bytes(firmware), firmware_pwms()), Answer(bytes(sim), sim_pwms()))
            )
    return greeting_fw, greeting_sim, results


def test_neither_board_says_anything_at_start_up(
    transcripts: tuple[Answer, Answer, list[tuple[Answer, Answer]]],
) -> None:
    firmware, sim, _ = transcripts
    assert firmware.sent == sim.sent == b""
    assert sim.pwms == firmware.pwms


@pytest.mark.parametrize("probe", PROBES, ids=[probe.name for probe in PROBES])
def test_the_simulated_plen2_answers_and_moves_as_its_firmware_does(
    probe: Probe, transcripts: tuple[Answer, Answer, list[tuple[Answer, Answer]]]
) -> None:
    _, _, results = transcripts
    firmware, sim = results[PROBES.index(probe)]
    if probe.name in KNOWN_DIFFERENCES:
        assert sim != firmware, f"no longer differs: drop {probe.name!r} from KNOWN_DIFFERENCES"
        return
    assert sim.sent == firmware.sent, probe.writes
    assert sim.pwms == firmware.pwms, probe.writes


def test_an_erased_slot_is_the_one_dump_that_differs() -> None:
    """:data:`ERASED_SLOT_DIFFERENCE`: both sides' first 0.3 s of ``<MO00`` on a new board."""
    with Board(
        build(plen2_32u4()),
        PLEN2_MCU,
        PLEN2_F_CPU_HZ,
        uart="1",
        baud=PLEN2_BAUD,
        eeprom=PLEN2_EEPROM,
    ) as board:
        board.advance_to(BOOT_S)
        firmware = board.exchange(b"<MO00", 0.3)
    plen2 = get_profile("plen2")
    profile = dataclasses.replace(plen2, options={"transport": "uart"})
    simulation = Simulation(load_world("empty"), profile, seed=1)
    simulation.connect()
    simulation.tick(BOOT_S, BOOT_S)
    simulation.write(b"<MO00")
    simulation.tick(BOOT_S + 0.3, 0.3)
    sim = simulation.read(simulation.in_waiting)
    assert firmware.startswith(b'{\r\n\t"slot": 255,\r\n\t"name": "' + b"\xff" * 20)
    assert len(firmware) > 10_000
    assert sim.startswith(b'{\r\n\t"slot": 0,') and sim.endswith(b'"frames": [\r\n\t]\r\n}\r\n')


def _servo_outputs_over(writes: list[tuple[bytes, float]]) -> list[tuple[tuple[int, ...], ...]]:
    """Both boards from power-on, each ``(bytes, then run seconds)`` in turn: the servo
    outputs of each after every write's run, firmware first."""
    elf = build(plen2_32u4())
    pwms = symbol_address(elf, PWMS)
    plen2 = get_profile("plen2")
    profile = dataclasses.replace(plen2, options={"transport": "uart"})
    simulation = Simulation(load_world("empty"), profile, seed=1, physics_dt_s=PROBE_STEP_S)
    simulation.connect()
    device = simulation.device
    assert isinstance(device, Plen2Board)
    outputs = []
    with Board(
        elf, PLEN2_MCU, PLEN2_F_CPU_HZ, uart="1", baud=PLEN2_BAUD, eeprom=PLEN2_EEPROM
    ) as board:
        board.advance_to(BOOT_S)
        simulation.tick(BOOT_S, BOOT_S)
        for data, run_s in writes:
            board.exchange(data, run_s)
            simulation.write(data)
            simulation.tick(board.time_s, run_s)
            firmware = struct.unpack(f"<{m.JOINT_COUNT}H", board.peek(pwms, 2 * m.JOINT_COUNT))
            sim = tuple(servo_pwm(angle) for angle in device.angles_ddeg)
            outputs.append((firmware, sim))
    return outputs


def test_an_erased_slot_played_on_a_new_board_moves_as_the_firmware_does() -> None:
    """A new board's frame buffers hold frames of 0 ms: the erased slot's refused frame
    reads leave one in place, and ``MotionController`` divides by its count of 0
    (avr-gcc's division gives -1): every joint goes a tenth of a degree below home."""
    [(firmware, sim)] = _servo_outputs_over([(b"$PM0a", 0.3)])
    assert sim == firmware


def test_a_frame_of_8192_ms_inside_a_motion_is_passed_over_as_the_firmware_does() -> None:
    """8192 ms is 256 updates, 0 in ``MotionController``'s ``uint8_t`` count: loaded just
    after an update, the frame is finished before the next one, and the frame after it
    starts from its values."""
    header = b">MH0bzero-count          0000000000003"
    frames = [timed_frame(11, 0, 64, 100), timed_frame(11, 1, 8192, -100)]
    frames.append(timed_frame(11, 2, 96, 50))
    writes = [(header[i : i + 32], CHUNK_GAP_S) for i in range(0, len(header), 32)]
    for frame in frames:
        writes += [(frame[i : i + 32], CHUNK_GAP_S) for i in range(0, len(frame), 32)]
    writes += [(b"$PM0b", 0.05), (b"", 0.05), (b"", 0.05), (b"", 0.5)]
    outputs = _servo_outputs_over(writes)[-4:]
    assert [sim for _, sim in outputs] == [firmware for firmware, _ in outputs]
    assert len({firmware for firmware, _ in outputs}) >= 3  # it moved on the way
