"""Run a probe set on the emulated firmware and on ``roboscript sim``, one answer per probe."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

from firmware.asip_probes import Probe
from firmware.avr import Board, build
from firmware.recipes import MIRTLE_BAUD, MIRTLE_F_CPU_HZ, MIRTLE_MCU, mirtle_328p

from roboscript.drivers.asip.device import RESET_GREETING_S
from roboscript.profiles import get_profile
from roboscript.sim.simulation import Simulation
from roboscript.sim.world import load_world

BOOT_S = 4.0
"""Long enough for the sketch's start-up (3.2 s of ``pixelFun`` delays, then ``setup()``)."""


def firmware_transcript(probes: Sequence[Probe]) -> tuple[bytes, list[bytes]]:
    """The emulated MIRTO board's start-up bytes and its answer to each probe in turn."""
    with Board(build(mirtle_328p()), MIRTLE_MCU, MIRTLE_F_CPU_HZ, baud=MIRTLE_BAUD) as board:
        greeting = board.advance_to(BOOT_S)
        answers = [board.exchange(probe.data, probe.settle_s) for probe in probes]
    return greeting, answers


def sim_transcript(
    probes: Sequence[Probe], *, after_greeting_s: float = BOOT_S - RESET_GREETING_S
) -> tuple[bytes, list[bytes]]:
    """``roboscript sim``'s MIRTO board, on a UART like the emulated 328P build: its start-up
    bytes and its answer to each probe in turn, the first sent ``after_greeting_s`` after
    the board started greeting (by default when the emulated board gets its first)."""
    mirto = get_profile("mirto")
    profile = dataclasses.replace(mirto, options={**mirto.options, "transport": "uart"})
    simulation = Simulation(load_world("empty"), profile, seed=1)
    simulation.connect()
    simulation.tick(after_greeting_s, after_greeting_s)
    greeting = simulation.read(simulation.in_waiting)
    answers = []
    for probe in probes:
        simulation.write(probe.data)
        end_s = simulation.time_s + probe.settle_s
        simulation.tick(end_s, probe.settle_s)
        answers.append(simulation.read(simulation.in_waiting))
    return greeting, answers
