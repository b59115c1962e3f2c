"""A MIRTO board that resets when its port opens, against the real firmware's start-up.

An Arduino UART board (an Uno-style MIRTO 328 V2) restarts when a host opens its port (the
DTR line drives its reset), so its sketch runs ``setup()`` again before it answers. The
emulated firmware boots from power-on, which is that reset; the simulated board with
``reset_on_connect`` boots from the connection. Both get the same bytes at the same times
(the driver's ``#,?`` every 250 ms, then requests every 5 ms across the moment the sketch
opens its UART) and must answer the same, at the same moments to the 5 ms physics step.
"""

from __future__ import annotations

import dataclasses

import pytest
from firmware.avr import Board, build
from firmware.recipes import MIRTLE_BAUD, MIRTLE_F_CPU_HZ, MIRTLE_MCU, mirtle_328p

from roboscript.drivers.asip.device import RESET_GREETING_S, RESET_UART_ON_S, MirtoBoard
from roboscript.profiles import get_profile
from roboscript.sim.simulation import Simulation
from roboscript.sim.world import load_world

STEP_S = 0.005
"""The simulation's physics step: the simulated board answers at step ends."""
END_S = 3.6
"""Past the start-up and the answers to what waited in the receive ring."""
_LETTERS = "ABCEFGHJKLNOQUVWXYZabcdefghijklmnopqrstuvwxyz"  # services the sketch lacks


def _writes() -> list[tuple[int, bytes]]:
    """(physics step, bytes) the host writes: ``#,?`` every 250 ms as the driver does, then
    an unknown service every 5 ms from 2.95 s, so that some arrive before the UART is on,
    some fill the receive ring while the board greets and the rest overflow it."""
    writes = [(step, b"#,?\n") for step in range(0, 590, 50)]
    writes += [(590 + index, f"{letter},?\n".encode()) for index, letter in enumerate(_LETTERS)]
    return writes


def _firmware() -> list[bytes]:
    """What the emulated board sent in each physics step, from power-on."""
    writes = dict(_writes())
    sent = []
    with Board(build(mirtle_328p()), MIRTLE_MCU, MIRTLE_F_CPU_HZ, baud=MIRTLE_BAUD) as board:
        for step in range(round(END_S / STEP_S)):
            if step in writes:
                board.write(writes[step])
            sent.append(board.advance_to((step + 1) * STEP_S))
    return sent


def _without_bootloader(simulation: Simulation) -> Simulation:
    """The simulated board built as the emulated one is: no bootloader (an Uno's optiboot
    would first take 0.39 to 1.37 s, see ``test_reset_on_connect.py``)."""
    board = simulation.device
    assert isinstance(board, MirtoBoard)
    board.config = dataclasses.replace(board.config, bootloader=False)
    return simulation


def _simulated() -> list[bytes]:
    """What ``roboscript sim``'s board sent in each physics step, from the connection."""
    mirto = get_profile("mirto")
    options = {**mirto.options, "transport": "uart", "reset_on_connect": True}
    simulation = Simulation(load_world("empty"), dataclasses.replace(mirto, options=options))
    _without_bootloader(simulation).connect()
    writes = dict(_writes())
    sent = [simulation.read(simulation.in_waiting)]  # the connection itself: nothing
    for step in range(round(END_S / STEP_S)):
        if step in writes:
            simulation.write(writes[step])
        simulation.tick((step + 1) * STEP_S, STEP_S)
        sent.append(simulation.read(simulation.in_waiting))
    sent[1] = sent[0] + sent[1]
    return sent[1:]


@pytest.fixture(scope="module")
def boots() -> tuple[list[bytes], list[bytes]]:
    return _firmware(), _simulated()


def _first_step(sent: list[bytes]) -> int:
    return next(step for step, data in enumerate(sent) if data)


def test_a_reset_board_is_silent_until_its_sketch_greets_as_the_firmware_is(
    boots: tuple[list[bytes], list[bytes]],
) -> None:
    firmware, simulated = boots
    assert _first_step(simulated) == _first_step(firmware)
    # the step the measured greeting time falls in
    assert _first_step(firmware) == int(RESET_GREETING_S / STEP_S)


def test_a_reset_board_answers_what_came_after_its_uart_opened_as_the_firmware_does(
    boots: tuple[list[bytes], list[bytes]],
) -> None:
    firmware, simulated = boots
    assert b"".join(simulated) == b"".join(firmware)


def test_the_probe_spans_the_uart_opening_and_an_overflowing_ring(
    boots: tuple[list[bytes], list[bytes]],
) -> None:
    """The schedule reaches the cases it is meant to (so the comparison above bites)."""
    answered = b"".join(boots[0])
    before = [w for w in _writes() if w[0] * STEP_S + 0.001 < RESET_UART_ON_S]
    assert b"~N,?" not in answered and before[-1][1] == b"N,?\n"  # sent before the UART was on
    assert b"~O,?" in answered  # the first after it
    assert b"~z,?" not in answered  # the ring overflowed while the board greeted
    assert answered.count(b"@#,?") == 0  # every driver probe came too early


RESET_STEP = 1000
"""The physics step at whose start both boards are reset mid-session (5 s: encoder and bump
events running, the driver's requests answered)."""
MID_END_S = 9.0
"""Past the second start-up and the answers to what waited in the receive ring."""


def _mid_session_writes() -> list[tuple[int, bytes]]:
    """(physics step, bytes): the driver's ``#,?`` every 250 ms until answered, its events
    turned on, then ``#,?`` every 250 ms again, across the reset and the second start-up."""
    writes = [(step, b"#,?\n") for step in range(0, 660, 50)]
    writes += [(700, b"M,A,1\nB,A,50\n")]
    writes += [(step, b"#,?\n") for step in range(900, round(MID_END_S / STEP_S), 50)]
    return writes


def _firmware_reset_mid_session() -> list[bytes]:
    writes = dict(_mid_session_writes())
    sent = []
    with Board(build(mirtle_328p()), MIRTLE_MCU, MIRTLE_F_CPU_HZ, baud=MIRTLE_BAUD) as board:
        for step in range(round(MID_END_S / STEP_S)):
            if step == RESET_STEP:
                board.reset()
            if step in writes:
                board.write(writes[step])
            sent.append(board.advance_to((step + 1) * STEP_S))
    return sent


def _simulated_reset_mid_session() -> list[bytes]:
    mirto = get_profile("mirto")
    options = {**mirto.options, "transport": "uart", "reset_on_connect": True}
    simulation = Simulation(load_world("empty"), dataclasses.replace(mirto, options=options))
    _without_bootloader(simulation).connect()
    writes = dict(_mid_session_writes())
    sent = []
    for step in range(round(MID_END_S / STEP_S)):
        if step == RESET_STEP:
            board = simulation.device
            assert isinstance(board, MirtoBoard)
            board.reset(simulation.time_s)  # the supply dipping: no bootloader
        if step in writes:
            simulation.write(writes[step])
        simulation.tick((step + 1) * STEP_S, STEP_S)
        sent.append(simulation.read(simulation.in_waiting))
    return sent


@pytest.fixture(scope="module")
def mid_session_resets() -> tuple[list[bytes], list[bytes]]:
    return _firmware_reset_mid_session(), _simulated_reset_mid_session()


def test_a_board_reset_mid_session_is_silent_then_greets_again_as_the_firmware_does(
    mid_session_resets: tuple[list[bytes], list[bytes]],
) -> None:
    firmware, simulated = mid_session_resets
    after = slice(RESET_STEP, None)
    # nothing more of what it was sending: the events stop with the reset, and the next byte
    # is the start of its greeting, when the sketch has started again
    assert _first_step(simulated[after]) == _first_step(firmware[after])
    assert _first_step(firmware[after]) == int(RESET_GREETING_S / STEP_S)
    assert firmware[RESET_STEP + _first_step(firmware[after])].startswith(b"!Mirtle2017 running")
    assert b"".join(simulated[after]) == b"".join(firmware[after])


def test_before_its_reset_the_board_answered_and_sent_events_as_the_firmware_did(
    mid_session_resets: tuple[list[bytes], list[bytes]],
) -> None:
    firmware, simulated = mid_session_resets
    before = b"".join(firmware[:RESET_STEP])
    assert b"@#,?,1,1,ATmega328P" in before and b"@M,e,2" in before and b"@B,e,2" in before
    assert b"".join(simulated[:RESET_STEP]) == before
