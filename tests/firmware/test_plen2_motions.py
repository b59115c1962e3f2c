"""roboscript's PLEN2 driver installs and plays its motions on PLEN2's own firmware.

The firmware (1.4.2, emulated ATmega32u4) keeps motions in an external 24FC1025 I2C EEPROM;
the harness attaches its own model of the part (page writes, the address pointer kept across
STOP, acknowledge polling while a write cycle runs), erased as delivered. A mission walks two
steps on it in lockstep (:mod:`firmware.plen2_lockstep`): the driver's handshake finds the
gait slots erased, writes its four gaits (the bytes it sends, paced as it paces them), reads
each back and checks it; then ``#PU``/``#PO`` play the walk. The firmware's servo outputs
(``m_pwms``, taken at the end of each 32 ms update of its motion controller) are compared,
update by update, with roboscript's simulated PLEN2 given the same bytes at the same times.
"""

from __future__ import annotations

import itertools
import struct
from dataclasses import dataclass

import pytest
from firmware.plen2_lockstep import EmulatedPlen2, ServoUpdate, firmware_as_plen2, servo_pwm
from firmware.plen2_lockstep import twin_updates as simulated_updates

from roboscript.codec import Role, readable
from roboscript.drivers.plen import messages as m
from roboscript.drivers.plen.codec import PlenCodec
from roboscript.drivers.plen.device import UPDATE_INTERVAL_S
from roboscript.drivers.plen.driver import CHUNK_BYTES, PlenDriver
from roboscript.drivers.plen.gaits import GAIT_KEYS, load_gait
from roboscript.mission import load_mission
from roboscript.profiles import get_profile
from roboscript.session import Session, run_session

LOCKSTEP_TIMEOUT = pytest.mark.timeout(900)
"""About 14 s of simulated time (an erased slot's 255-frame dump takes 5 of them): tens of
seconds of emulation on a loaded machine; lockstep makes the result independent of that."""
STEPS = 2
TWO_STEPS = f"""\
mission: two steps
robot: plen2
initial: forward
states:
  forward:
    do: {{walk: {{steps: {STEPS}}}}}
    timeout: 10 s
    on: {{done: rest, timeout: stuck}}
  rest:
    final: success
  stuck:
    final: failure
"""
EEPROM_BLOCK_BYTES = 0x10000
"""``ExternalEEPROM.cpp``: an address past 64 KiB selects the part's second block (0x54)."""
CHUNK_SIZE, SLOT_SIZE = 32, 30
"""``ExternalEEPROM.h``: each 32-byte chunk holds 30 bytes of data (Wire's 32-byte buffer
less the two address bytes)."""
CHUNKS_PER_MOTION = 1 + 2 * m.FRAME_LENGTH_MAX
"""``Motion.cpp``: a 30-byte header takes one chunk and a 51-byte frame two, 20 frames."""


@dataclass
class Run:
    session: Session
    board: EmulatedPlen2
    motion_memory: dict[int, bytes]
    """Each gait slot's chunks as the EEPROM held them at the end, by slot."""
    pwms: tuple[int, ...]
    """The servo outputs at the end."""
    timer_samples: list[tuple[int, int, int, int]]
    """(multiplexer line selected, OCR1C, OCR1B, OCR1A) sampled every millisecond at the end."""


# ATmega32u4 data addresses; Pin.h: multiplexer select lines on pins 5, 6, 12 (PC6, PD7, PD6)
_PORTC, _PORTD, _OCR1A = 0x28, 0x2B, 0x88


def _timer_sample(board: EmulatedPlen2) -> tuple[int, int, int, int]:
    portc, portd = board.board.peek(_PORTC)[0], board.board.peek(_PORTD)[0]
    line = (portc >> 6 & 1) | (portd >> 7 & 1) << 1 | (portd >> 6 & 1) << 2
    ocr1a, ocr1b, ocr1c = struct.unpack("<3H", board.board.peek(_OCR1A, 6))
    return line, ocr1c, ocr1b, ocr1a


def _motion_memory(board: EmulatedPlen2, slot: int) -> bytes:
    address = slot * CHUNKS_PER_MOTION * CHUNK_SIZE
    block, offset = divmod(address, EEPROM_BLOCK_BYTES)
    return board.board.read_eeprom(block, offset, CHUNKS_PER_MOTION * CHUNK_SIZE)


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> Run:
    mission = tmp_path_factory.mktemp("plen2") / "two_steps.yaml"
    mission.write_text(TWO_STEPS, encoding="utf-8")
    spec, _ = load_mission(mission)
    with pytest.MonkeyPatch.context() as monkeypatch, firmware_as_plen2(monkeypatch) as boards:
        session = run_session(spec, get_profile("plen2"), max_time_s=120, runaway_after_s=None)
        board = boards[0]
        memory = {
            load_gait(key).slot: _motion_memory(board, load_gait(key).slot) for key in GAIT_KEYS
        }
        samples = []
        for _ in range(40):
            board.board.advance(0.001)
            sample = _timer_sample(board)
            board.board.advance(0.00005)
            # a sample taken while the overflow interrupt loads the compare registers (some
            # loaded, some not) differs from one 50 us later: it is not kept
            if _timer_sample(board) == sample:
                samples.append(sample)
        return Run(session, board, memory, board.servo_pwms(), samples)


def _chunk_data(run: Run, slot: int, chunk: int, count: int) -> bytes:
    """``count`` bytes of the ``chunk``-th chunk of ``slot``'s motion."""
    return run.motion_memory[slot][chunk * CHUNK_SIZE : chunk * CHUNK_SIZE + count]


@LOCKSTEP_TIMEOUT
def test_the_driver_writes_its_gaits_to_an_erased_plen2_and_reads_each_back_equal(
    run: Run,
) -> None:
    result = run.session.result
    assert result.outcome == "success", result.reason
    driver = run.session.robot.driver
    assert isinstance(driver, PlenDriver)
    # the driver's own read-back compared each dump from the firmware with what it wrote
    assert driver.installed == list(GAIT_KEYS)
    writes = [data for _, data in run.board.sent]
    assert all(len(data) <= CHUNK_BYTES for data in writes)
    sent = b"".join(writes)
    for key in GAIT_KEYS:
        gait = load_gait(key)
        assert gait.install_bytes() in sent


@LOCKSTEP_TIMEOUT
def test_the_firmware_keeps_each_gait_in_its_external_eeprom_in_its_own_layout(run: Run) -> None:
    for key in GAIT_KEYS:
        gait = load_gait(key)
        header = _chunk_data(run, gait.slot, 0, SLOT_SIZE)
        assert header[0] == gait.slot
        assert header[1:21].rstrip(b" ") == gait.header.name.encode()
        assert header[22] == gait.header.frame_length
        flags = header[23]  # avr-gcc packs the bit-fields from bit 0: use_loop is bit 7
        assert bool(flags & 0x80) == gait.header.use_loop
        assert bool(flags & 0x40) == gait.header.use_jump
        assert tuple(header[24:27]) == (
            gait.header.loop_begin,
            gait.header.loop_end,
            gait.header.loop_count,
        )
        for frame in gait.frames:
            chunk = 1 + 2 * frame.index
            stored = _chunk_data(run, gait.slot, chunk, SLOT_SIZE) + _chunk_data(
                run, gait.slot, chunk + 1, 21
            )
            index, time_ms, *values = struct.unpack(f"<BH{m.JOINT_COUNT}h", stored)
            assert (index, time_ms, tuple(values)) == (
                frame.index,
                frame.transition_time_ms,
                frame.offsets_ddeg,
            )


def _frame_ends(key: str, passes: int) -> list[tuple[int, tuple[int, ...]]]:
    """(update number, joint offsets) at the end of each frame of ``passes`` passes of a gait
    that loops over all its frames (``transition_time_ms // 32`` updates a frame)."""
    gait = load_gait(key)
    ends = []
    update = 0
    for _ in range(passes):
        for frame in gait.frames:
            update += frame.transition_time_ms // 32
            ends.append((update - 1, frame.offsets_ddeg))
    return ends


@LOCKSTEP_TIMEOUT
def test_the_walk_moves_the_firmwares_servos_frame_by_frame_as_the_gait_says(run: Run) -> None:
    updates = run.board.updates
    ends = _frame_ends("walk_forward", STEPS)
    assert len(updates) == ends[-1][0] + 1
    home = m.FACTORY_HOME_DDEG
    for update, offsets in ends:
        expected = [servo_pwm(home[j] + offsets[j]) for j in range(m.JOINT_COUNT)]
        # the fixed-point steps can end a frame one tenth of a degree short
        assert all(
            abs(got - want) <= 1 for got, want in zip(updates[update].pwms, expected, strict=True)
        ), update
    # the servos really move: every joint the gait uses changes over the walk
    moved = {j for j in range(m.JOINT_COUNT) if len({u.pwms[j] for u in updates}) > 1}
    used = {j for _, offsets in ends for j, value in enumerate(offsets) if value}
    assert used and used <= moved


@LOCKSTEP_TIMEOUT
def test_timer_1_sends_each_servo_output_to_its_multiplexer_line(run: Run) -> None:
    # JointController.cpp, ISR(TIMER1_OVF_vect): each 4.096 ms overflow selects line n and
    # loads line n + 1's widths (OCR1C: joints 0-7, OCR1B: 8-15, OCR1A: 16-23), which the
    # double-buffered compare registers take at the next period, when line n + 1 is selected.
    assert {line for line, *_ in run.timer_samples} == set(range(8))
    for line, ocr1c, ocr1b, ocr1a in run.timer_samples:
        ahead = (line + 1) % 8
        assert (ocr1c, ocr1b, ocr1a) == (run.pwms[ahead], run.pwms[8 + ahead], run.pwms[16 + ahead])


def _gaps(updates: list[ServoUpdate]) -> list[float]:
    return [b.time_s - a.time_s for a, b in itertools.pairwise(updates)]


@LOCKSTEP_TIMEOUT
def test_the_simulated_plen2_drives_its_servos_update_by_update_as_the_firmware(
    run: Run,
) -> None:
    firmware = run.board.updates
    simulated = simulated_updates(run.board.sent, run.board.board.time_s)
    assert [u.pwms for u in simulated] == [u.pwms for u in firmware]
    # Timer 1 paces the firmware's updates 32.768 ms apart after the first, which comes as
    # soon as the motion is read (the due flag stayed set while nothing played); each ends
    # after the simulated one by the update's own running time (24 map() calls, about
    # 1 ms), the EEPROM reads of a new frame and Timer 1's phase (set up during setup()).
    assert _gaps(firmware)[1:] == pytest.approx([UPDATE_INTERVAL_S] * (len(firmware) - 2), abs=5e-4)
    lag = [f.time_s - s.time_s for f, s in zip(firmware, simulated, strict=True)]
    assert min(lag) >= 0 and max(lag) < UPDATE_INTERVAL_S / 4


@LOCKSTEP_TIMEOUT
def test_each_gait_the_firmware_dumps_after_the_install_is_the_one_installed(run: Run) -> None:
    codec = PlenCodec(Role.HOST)
    codec.receive_data(bytes(run.board.board.received))
    dumps = [reply for reply in readable(codec) if isinstance(reply, m.MotionReply)]
    for key in GAIT_KEYS:
        assert load_gait(key).stored in dumps
