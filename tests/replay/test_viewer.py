"""What the replay viewer embeds of a run."""

from __future__ import annotations

from typing import Any

from roboscript.replay.recording import fill_frames
from roboscript.replay.viewer import decimate


def test_fewer_frames_a_second_still_keep_a_state_entered_again_for_the_same_cause() -> None:
    # entered at 0 s, then again every 0.3 s because its wait was done: equal causes
    deltas: list[dict[str, Any]] = [{"t": 0.0, "state": "wait", "why": {"kind": "start"}}]
    for tick in range(1, 40):
        t = round(tick * 0.02, 2)
        deltas.append({"t": t, "why": {"kind": "done"}} if tick % 15 == 0 else {"t": t})
    kept = decimate(fill_frames(deltas), rate_hz=1.0)
    assert [f["t"] for f in kept] == [0.0, 0.3, 0.6, 0.78]  # each transition, and the end


def test_fewer_frames_a_second_still_keep_every_printed_line_at_its_tick() -> None:
    deltas: list[dict[str, Any]] = [{"t": 0.0, "state": "go", "why": {"kind": "start"}}]
    for tick in range(1, 40):
        t = round(tick * 0.02, 2)
        deltas.append({"t": t, "print": [f"tick {tick}", "again"]} if tick % 7 == 0 else {"t": t})
    kept = decimate(fill_frames(deltas), rate_hz=1.0)
    printed = [(f["t"], line) for f in kept for line in f.get("print", [])]
    assert printed == [
        (round(tick * 0.02, 2), line)
        for tick in range(7, 40, 7)
        for line in (f"tick {tick}", "again")
    ]
