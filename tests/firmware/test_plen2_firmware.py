"""roboscript's simulated PLEN2 against PLEN2's own firmware.

The firmware (``plen-Firmware_Arduino`` 1.4.2) runs unchanged on an emulated ATmega32u4 at
16 MHz. It answers on USB serial, which the emulator lacks, so its replies are sent to UART1
(2 Mbaud) instead (one forced ``#define``, ``shims/plen2/replies_on_uart1.h``). Each request
goes to it and to ``roboscript sim``'s PLEN2 the way the driver paces it (32-byte writes 50 ms
apart), and every answer is compared byte for byte.

Motions live in the board's external I2C EEPROM (a 24FC1025), attached here as the harness's
own model of the part; installing, reading back and playing motions against the firmware is
``test_plen2_motions.py``.
"""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from firmware.avr import Board, build
from firmware.recipes import PLEN2_BAUD, PLEN2_EEPROM, PLEN2_F_CPU_HZ, PLEN2_MCU, plen2_32u4

from roboscript.drivers.plen.driver import CHUNK_BYTES, CHUNK_GAP_S
from roboscript.sim.simulation import Simulation, make_simulation

GETTER_S = 0.5
"""Time for a getter's reply (``<JS`` prints about 2 KB of JSON at 2 Mbaud)."""

REQUESTS: list[tuple[str, bytes]] = [
    ("version", b"<VI"),
    ("joint settings", b"<JS"),
    ("set a home position", b">HO000010"),
    ("joint settings after it", b"<JS"),
    ("factory joint settings", b">JS"),
    ("joint settings restored", b"<JS"),
]


def _paced(data: bytes) -> Iterator[bytes]:
    for start in range(0, len(data), CHUNK_BYTES):
        yield data[start : start + CHUNK_BYTES]


def _sim_answer(simulation: Simulation, data: bytes, now_s: float) -> tuple[bytes, float]:
    for chunk in _paced(data):
        simulation.write(chunk)
        now_s += CHUNK_GAP_S
        simulation.tick(now_s, CHUNK_GAP_S)
    now_s += GETTER_S
    simulation.tick(now_s, GETTER_S)
    return simulation.read(simulation.in_waiting), now_s


@pytest.fixture(scope="module")
def answers() -> list[tuple[bytes, bytes]]:
    simulation = make_simulation("plen2")
    simulation.connect()
    now_s = 0.0
    results = []
    elf = build(plen2_32u4())
    with Board(
        elf, PLEN2_MCU, PLEN2_F_CPU_HZ, uart="1", baud=PLEN2_BAUD, eeprom=PLEN2_EEPROM
    ) as board:
        board.advance_to(1.0)  # setup(): serial, EEPROM, joint settings
        for _, data in REQUESTS:
            firmware = bytearray()
            for chunk in _paced(data):
                firmware += board.exchange(chunk, CHUNK_GAP_S)
            firmware += board.advance(GETTER_S)
            sim, now_s = _sim_answer(simulation, data, now_s)
            results.append((bytes(firmware), sim))
    return results


@pytest.mark.parametrize("index", range(len(REQUESTS)), ids=[name for name, _ in REQUESTS])
def test_the_simulated_plen2_answers_as_its_firmware_does(
    index: int, answers: list[tuple[bytes, bytes]]
) -> None:
    firmware, sim = answers[index]
    assert sim == firmware
