"""Benchmark 10: the real firmware on the emulated AVR: its speed in lockstep and the tier's cost.

* **Emulated speed in lockstep**: the MIRTO firmware (``mirtle2017`` on an ATmega328P at
  16 MHz) advanced one 20 ms mission tick at a time, its encoders turning as its motors
  drive, one harness round trip per mission tick, as ``tests/firmware/test_mirto_missions.py`` runs
  whole missions. Reported as simulated seconds per wall second, and against the same
  firmware run free (one long advance), which is the emulator's own speed: the ratio is what
  lockstep costs.
* **The tier's cost**: a cold build of each firmware (empty cache: Arduino core, libraries,
  sketch), the harness's compile, and the ASIP probe set on both boards. CI pays the builds
  once per machine (they are cached by the hash of their inputs).

Needs the firmware tier's toolchain (``tests/firmware``); without it the rows say why.
Run alone: ``python tests/bench/bench_firmware.py [--quick]``.
"""

from __future__ import annotations

import os
import sys
import tempfile
import time
from pathlib import Path

from benchlib import Row, info, run_alone

TESTS = Path(__file__).resolve().parents[1]
if str(TESTS) not in sys.path:
    sys.path.insert(0, str(TESTS))

from firmware.avr import Board, build, harness, missing_prerequisite  # noqa: E402
from firmware.mirto_lockstep import motor_power  # noqa: E402
from firmware.recipes import (  # noqa: E402
    MIRTLE_F_CPU_HZ,
    MIRTLE_MCU,
    mirtle_328p,
    stackmod_328p,
)

__all__ = ["measure"]

STEP_S = 0.02
"""The mission tick (roboscript.robot.DEFAULT_PERIOD_S): one harness round trip each."""
BOOT_S = 4.0


def lockstep_speed(duration_s: float) -> tuple[float, float]:
    """Simulated seconds per wall second: (in 5 ms lockstep steps, free-running)."""
    with Board(build(mirtle_328p()), MIRTLE_MCU, MIRTLE_F_CPU_HZ) as board:
        board.turn_encoder(0, "D", 3, 7, 0, 0)
        board.turn_encoder(1, "D", 2, 4, 0, 0)
        board.advance_to(BOOT_S)
        board.exchange(b"M,A,1\nM,R,60,60,60000\n", 0.05)
        started = time.perf_counter()
        steps = round(duration_s / STEP_S)
        end_s = board.time_s
        for _ in range(steps):
            end_s += STEP_S
            _, registers = board.step(end_s, (32, 32), 0x25, 0x24)
            motor_power(registers)
        lockstep = steps * STEP_S / (time.perf_counter() - started)
        started = time.perf_counter()
        board.advance(duration_s)
        free = duration_s / (time.perf_counter() - started)
    return lockstep, free


def tier_cost() -> dict[str, float]:
    """Wall seconds of each part of the tier, from an empty build cache."""
    from firmware.asip_probes import PROBES
    from firmware.transcripts import firmware_transcript, sim_transcript

    costs: dict[str, float] = {}
    saved = os.environ.get("ROBOSCRIPT_FIRMWARE_CACHE")
    with tempfile.TemporaryDirectory() as cache:
        os.environ["ROBOSCRIPT_FIRMWARE_CACHE"] = cache
        try:
            for name, step in (
                ("harness compile", harness),
                ("MIRTO firmware build", lambda: build(mirtle_328p())),
                ("StackMod firmware build", lambda: build(stackmod_328p())),
                ("ASIP probe set, firmware", lambda: firmware_transcript(PROBES)),
                ("ASIP probe set, sim", lambda: sim_transcript(PROBES)),
            ):
                started = time.perf_counter()
                step()
                costs[name] = time.perf_counter() - started
        finally:
            if saved is None:
                del os.environ["ROBOSCRIPT_FIRMWARE_CACHE"]
            else:
                os.environ["ROBOSCRIPT_FIRMWARE_CACHE"] = saved
    return costs


def measure(quick: bool = False) -> list[Row]:
    """The emulated firmware's speed in lockstep, and the tier's cost."""
    reason = missing_prerequisite()
    if reason is not None:
        print(f"firmware benchmark skipped: {reason}", file=sys.stderr)
        return []
    duration_s = 1.0 if quick else 5.0
    lockstep, free = lockstep_speed(duration_s)
    rows = [
        info(
            "10",
            "emulated MIRTO firmware in lockstep (simulated s per wall s)",
            lockstep,
            f"{duration_s:g} s of driving in 20 ms ticks, encoders turning; 16 MHz ATmega328P",
        ),
        info(
            "10",
            "lockstep ÷ free-running emulation (what the step round trips cost)",
            lockstep / free,
            f"free-running {free:.2f} simulated s per wall s",
        ),
    ]
    costs = tier_cost()
    total = sum(costs.values())
    rows.append(
        info(
            "10",
            "firmware tier set-up from an empty cache (wall s)",
            total,
            "; ".join(f"{name} {seconds:.1f} s" for name, seconds in costs.items()),
            unit=" s",
        )
    )
    return rows


if __name__ == "__main__":
    run_alone(__doc__, measure, "1 s of lockstep, not 5 s")
