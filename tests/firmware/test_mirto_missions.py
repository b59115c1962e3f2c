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

CORNER_TOLERANCE_DEG = 2.0
"""How far from 90 degrees a corner may end on the firmware: the rotate action settles within
1 degree of its encoder angle, and slip makes the body turn up to about 1 degree less."""
CLOSING_MM = 60.0
"""How far from its start the square may end: a heading 1, 2 and 3 degrees off over the
second, third and fourth 50 cm side moves the end by 500 mm × sin(6°) ≈ 52 mm."""

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
    # Each corner settles within the rotate action's 1 degree on the encoders the firmware
    # counts; the simulated wheels' slip (about 1 %) moves the body up to another degree.
    turns = _corner_turns_deg(path, result.states)
    assert turns == pytest.approx([90.0] * 4, abs=CORNER_TOLERANCE_DEG)
    # So the square closes as on the simulated board: the heading within the four corners'
    # tolerance, and the end within what those headings make of four 50 cm sides.
    _, x_mm, y_mm, heading_deg = path[-1]
    assert abs((heading_deg + 180.0) % 360.0 - 180.0) <= 4 * CORNER_TOLERANCE_DEG
    assert math.hypot(x_mm, y_mm) <= CLOSING_MM


def _corner_turns_deg(
    path: list[tuple[float, float, float, float]], states: list[tuple[float, str]]
) -> list[float]:
    """How far the body turned over each corner, degrees, clockwise positive: from the
    heading where the side before it ended to the heading where the next side (or the
    mission's end) began."""
    starts = [t for t, state in states if state == "side"] + [path[-1][0]]
    corners = [t for t, state in states if state == "corner"]
    turns = []
    for corner_s, next_s in zip(corners, starts[1:], strict=True):
        before = [sample for sample in path if sample[0] <= corner_s][-1]
        after = next(sample for sample in path if sample[0] >= next_s)
        turns.append((after[3] - before[3] + 180.0) % 360.0 - 180.0)
    return turns


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
