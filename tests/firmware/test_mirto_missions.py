"""Whole missions on the real MIRTO firmware, in lockstep with the mission clock.

The emulated ATmega328P runs the ``mirtle2017`` sketch as the simulator's device: its PID
drives the simulated wheels and the wheels turn its encoders (:mod:`firmware.mirto_lockstep`).
The board boots as on power-up (3.2 s of start-up before it answers), so the driver's
handshake waits for it as it would for a board that resets when its port opens.
"""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import pytest
from firmware.mirto_lockstep import firmware_as_mirto

from roboscript.mission import load_mission
from roboscript.profiles import get_profile
from roboscript.session import Session, run_session

MISSIONS = Path(__file__).resolve().parents[2] / "missions"
LOCKSTEP_TIMEOUT = pytest.mark.timeout(900)
"""A whole mission is hundreds of millions of AVR cycles: about 30 s of emulation on an idle
core, several times that on a loaded machine. Lockstep makes the result independent of that;
only the wall-clock allowance has to cover it."""

SHORT_DRIVE = """\
mission: short drive
initial: side
states:
  side:
    do: {drive: {distance: 20 cm, speed: 15 cm/s}}
    timeout: 5 s
    on: {done: finished, failed: stuck, timeout: stuck}
  stuck:
    final: failure
  finished:
    final: success
"""


def _run(path: Path, monkeypatch: pytest.MonkeyPatch) -> tuple[Session, bytes]:
    spec, _ = load_mission(path)
    with firmware_as_mirto(monkeypatch) as boards:
        session = run_session(spec, get_profile("mirto"), max_time_s=60, runaway_after_s=None)
        return session, bytes(boards[0].board.received)


@LOCKSTEP_TIMEOUT
def test_square_runs_to_success_on_the_firmware_with_four_sides_and_corners(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    session, received = _run(MISSIONS / "square.yaml", monkeypatch)
    result = session.result
    assert result.outcome == "success", result.reason
    assert [state for _, state in result.states].count("corner") == 4
    assert received.startswith(b"!Mirtle2017 running on ATmega328P")
    assert b"@M,e,2,{" in received  # the driver followed the firmware's own encoder events
    path = session.mission_path()
    travelled_mm = sum(math.dist(a[1:3], b[1:3]) for a, b in itertools.pairwise(path))
    assert 1800 <= travelled_mm <= 2200  # four 50 cm sides under the firmware's PID


@LOCKSTEP_TIMEOUT
def test_a_mission_on_the_firmware_is_the_same_run_byte_for_byte_every_time(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    mission = tmp_path / "short.yaml"
    mission.write_text(SHORT_DRIVE, encoding="utf-8")
    first, first_bytes = _run(mission, monkeypatch)
    second, second_bytes = _run(mission, monkeypatch)
    assert first.result.outcome == "success"
    assert first_bytes == second_bytes
    assert first.mission_path() == second.mission_path()
