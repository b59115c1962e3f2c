"""roboscript's simulated MIRTO board against the real ASIP V1.1 firmware with the MIRTO sketch.

The firmware (ASIP V1.1 library, sketch ``mirtle2017``, ATmega328P build, 57600 baud UART)
runs on an emulated AVR; ``roboscript sim``'s board gets the same probes on the same schedule.
Every answer must be byte-identical, except the differences listed in ``KNOWN_DIFFERENCES``,
each with the firmware line that decides it (docs/robots/mirto.md lists them too). A listed
difference that goes away fails its test too, so the list stays true.
"""

from __future__ import annotations

import pytest
from firmware.asip_probes import PROBES, SETTLE_S, Probe
from firmware.avr import Board, build
from firmware.recipes import MIRTLE_BAUD, MIRTLE_F_CPU_HZ, MIRTLE_MCU, mirtle_328p
from firmware.transcripts import BOOT_S, firmware_transcript, sim_transcript

from roboscript.drivers.asip.device import RESET_GREETING_S

KNOWN_DIFFERENCES: dict[str, str] = {
    "ir events": (
        "the IR values are the simulated floor's; the emulated board's ADC inputs read 0 V"
    ),
    "distance events": (
        "mirtle2017.ino: `NBR_DISTANCE_SENSORS = 1`; roboscript's mirto profile has a second, "
        "right-facing sensor (a sketch built with 2)"
    ),
    "distance measure": "the same second distance sensor",
    **dict.fromkeys(
        ("bump events every 2 ms", "bump events off after 2 ms"),
        "events as fast as the line takes them: both boards read a request between two "
        "events, each written as the line frees the buffer, but asip.cpp's service() reads "
        "the newline `B,A,2`'s parseInt left in front of `B,A,0` in a turn of its own (one "
        "byte up to ' ', once 4 are there), so the firmware writes one event more (14 bytes) "
        "before it reads the request (91 bytes after `B,A,0`, the simulated board 77), where "
        "the simulated board's reader drops leading newlines with the request",
    ),
    "range: input on an encoder pin": (
        "the pin's level follows the wheel (the Encoder library's pulled-up A and B lines): "
        "the simulated wheels turned during the motor probes and stopped between two "
        "quadrature states' edges, where the emulated board has no wheels and its lines "
        "never move (`@I,d,4,80`)"
    ),
    "unknown service, digits tail": (
        "which byte each skip after an error ends on turns on microseconds of the firmware's "
        "loop (the same firmware answers X 3 8 3 3 6 or X 3 8 3 3 7 with the request 6 us "
        "later: test_which_digits_the_firmware_reads_turns_on_microseconds_of_its_loop); the "
        "simulated board answers X 3 8 3 2 6, each skip within a byte of the firmware's"
    ),
    "requests behind long replies": (
        "which of the requests that arrive while the receive ring is full are lost turns on "
        "microseconds of the firmware's loop: the emulated board keeps one byte more of the "
        "last one (`~,,?,1{INVALID_SERVICE}` for its `,1`)"
    ),
    **dict.fromkeys(
        ("unknown services behind long replies", "version at the end"),
        "what the probe before left in the board differs (above), and is answered here",
    ),
    "range: pixel strip 1": (
        "asipPixels.cpp reads `stripPtr[stripIndex]` unchecked past its one strip "
        "(undefined: this build reads a count of 9 there); the simulated board answers "
        "~P,I,7{INVALID_DEVICE_NUMBER}"
    ),
    "an unknown strip's pixel count": (
        "asipPixels.cpp reads `stripPtr[stripIndex]` unchecked (`// todo - validate "
        "stripIndex range`), past its one strip: undefined; the simulated board answers "
        "~P,I,7{INVALID_DEVICE_NUMBER}"
    ),
}


JOINED_WITH_NEXT = frozenset({"bump events every 7 ms"})
"""Probes whose events run until the next probe turns them off, and whose split between the
two answers turns on where an event falls against the probe's end (both boards hand their
USART a byte every 170 us): each is compared together with the next probe's answer (and
that probe with nothing)."""


def _answer(answers: list[bytes], index: int) -> bytes:
    """A probe's answer as compared: joined with the next one's (see JOINED_WITH_NEXT)."""
    if PROBES[index].name in JOINED_WITH_NEXT:
        return answers[index] + answers[index + 1]
    if index and PROBES[index - 1].name in JOINED_WITH_NEXT:
        return b""
    return answers[index]


@pytest.fixture(scope="module")
def transcripts() -> tuple[tuple[bytes, list[bytes]], tuple[bytes, list[bytes]]]:
    return firmware_transcript(PROBES), sim_transcript(PROBES)


def test_sim_greets_a_host_with_the_sketchs_start_up_lines(
    transcripts: tuple[tuple[bytes, list[bytes]], tuple[bytes, list[bytes]]],
) -> None:
    (firmware_greeting, _), (sim_greeting, _) = transcripts
    assert sim_greeting == firmware_greeting


@pytest.mark.parametrize("probe", PROBES, ids=[probe.name for probe in PROBES])
def test_sim_answers_each_probe_as_the_firmware_does(
    probe: Probe,
    transcripts: tuple[tuple[bytes, list[bytes]], tuple[bytes, list[bytes]]],
) -> None:
    (_, firmware_answers), (_, sim_answers) = transcripts
    index = PROBES.index(probe)
    firmware, sim = _answer(firmware_answers, index), _answer(sim_answers, index)
    if probe.name in KNOWN_DIFFERENCES:
        assert sim != firmware, f"no longer differs: drop {probe.name!r} from KNOWN_DIFFERENCES"
    else:
        assert sim == firmware, f"{probe.data!r}: firmware {firmware!r}, sim {sim!r}"


def _services_read(answer: bytes) -> str:
    """The service letters a run of ``~S,?,1{INVALID_SERVICE}`` errors answered, in order."""
    return "".join(chr(line[1]) for line in answer.split(b"\n") if line.startswith(b"~"))


def test_which_digits_the_firmware_reads_turns_on_microseconds_of_its_loop() -> None:
    """``X,`` and 80 digits: what is skipped after each error is what has arrived when the
    error is written, so a request moved by 6 us (a sixth of a turn of ``loop()``) is read
    otherwise by the firmware itself; the simulated board gives one of its answers
    (docs/robots/mirto.md, "Timing on a uart board")."""
    probe = b"X," + b"0123456789" * 8 + b"\n"
    firmware = set()
    for moved_s in (0.0, 6e-6):
        with Board(build(mirtle_328p()), MIRTLE_MCU, MIRTLE_F_CPU_HZ, baud=MIRTLE_BAUD) as board:
            board.advance_to(BOOT_S + moved_s)
            firmware.add(_services_read(board.exchange(probe, SETTLE_S)))
    assert firmware == {"X38336", "X38337"}
    (_, [sim]) = sim_transcript(
        [Probe("digits", probe)], after_greeting_s=BOOT_S - RESET_GREETING_S
    )
    # the digits cycle 0-9: a skip that ends a byte sooner reads the digit before
    read = _services_read(sim)
    assert len(read) == 6 and read[:4] == "X383"
    for answer in firmware:
        assert all(
            (int(a) - int(b)) % 10 in (0, 1, 9) for a, b in zip(read[1:], answer[1:], strict=True)
        )
