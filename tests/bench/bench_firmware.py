"""Benchmark 10: the real firmware on the emulated AVR: its speed in lockstep and the tier's cost.

* **Emulated speed in lockstep**: the MIRTO firmware (``mirtle2017`` on an ATmega328P at
  16 MHz) advanced one 20 ms mission tick at a time, its encoders turning as its motors
  drive, one harness round trip per mission tick, as ``tests/firmware/test_mirto_missions.py`` runs
  whole missions. Reported as simulated seconds per CPU second (the emulator's process and
  the host's: what it costs whatever else the machine runs; the wall-clock figure and the load
  it was measured at are given beside it), and against the same firmware run free (one long
  advance), which is the emulator's own speed: the ratio is what lockstep costs.
* **The tier's cost in CI**: each firmware's cold build (empty cache: Arduino core, libraries,
  sketch) and the harness's compile, a build taken from the cache (hashing its inputs), and
  the whole tier (``pytest tests/firmware``) with a warm cache, each as wall seconds and as
  CPU seconds of every process it ran (compilers, emulators, pytest). The CPU seconds are what
  the tier costs; the wall seconds equal them on an idle machine and grow with its load (the
  table says the load average each was measured at). CI pays the builds once per machine
  (they are cached by the hash of their inputs). ``--quick`` leaves out the whole-tier run.

Needs the firmware tier's toolchain (``tests/firmware``); without it the rows say why.
Run alone: ``python tests/bench/bench_firmware.py [--quick]``.
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
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
    plen2_32u4,
    stackmod_328p,
)

__all__ = ["measure"]

STEP_S = 0.02
"""The mission tick (roboscript.robot.DEFAULT_PERIOD_S): one harness round trip each."""
BOOT_S = 4.0


def _board_cpu_s(board: Board) -> float:
    """CPU seconds the emulator's process and this one have used so far (Linux /proc)."""
    with open(f"/proc/{board.pid}/stat", encoding="ascii") as stat:
        fields = stat.read().rsplit(")", 1)[1].split()
    emulator = (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    return emulator + time.process_time()


def lockstep_speed(duration_s: float) -> dict[str, float]:
    """Simulated seconds per wall second and per CPU second (the emulator's and this
    process's), in 20 ms lockstep steps and free-running."""
    speeds: dict[str, float] = {}
    with Board(build(mirtle_328p()), MIRTLE_MCU, MIRTLE_F_CPU_HZ) as board:
        board.turn_encoder(0, "D", 3, 7, 0, 0)
        board.turn_encoder(1, "D", 2, 4, 0, 0)
        board.advance_to(BOOT_S)
        board.exchange(b"M,A,1\nM,R,60,60,60000\n", 0.05)
        wall, cpu = time.perf_counter(), _board_cpu_s(board)
        steps = round(duration_s / STEP_S)
        end_s = board.time_s
        for _ in range(steps):
            end_s += STEP_S
            _, registers = board.step(end_s, (32, 32), 0x25, 0x24)
            motor_power(registers)
        speeds["lockstep wall"] = steps * STEP_S / (time.perf_counter() - wall)
        speeds["lockstep cpu"] = steps * STEP_S / (_board_cpu_s(board) - cpu)
        wall, cpu = time.perf_counter(), _board_cpu_s(board)
        board.advance(duration_s)
        speeds["free wall"] = duration_s / (time.perf_counter() - wall)
        speeds["free cpu"] = duration_s / (_board_cpu_s(board) - cpu)
    return speeds


@dataclass(frozen=True)
class Cost:
    """What one part of the tier took: wall seconds, CPU seconds (this process and every
    child it waited for), and the machine's 1-minute load average when it ended."""

    wall_s: float
    cpu_s: float
    load: float


def _cpu_s() -> float:
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def _timed(step: Callable[[], object]) -> Cost:
    wall, cpu = time.perf_counter(), _cpu_s()
    step()
    return Cost(time.perf_counter() - wall, _cpu_s() - cpu, os.getloadavg()[0])


def _whole_tier() -> None:
    """``pytest tests/firmware`` in a child process (the cache is the one set now)."""
    subprocess.run(
        [sys.executable, "-m", "pytest", str(TESTS / "firmware"), "-q", "-p", "no:cacheprovider"],
        cwd=TESTS.parent,
        check=True,
        capture_output=True,
    )


def tier_cost(quick: bool = False) -> dict[str, Cost]:
    """What each part of the tier costs, from an empty build cache, then with it warm."""
    recipes = (("MIRTO", mirtle_328p), ("StackMod", stackmod_328p), ("PLEN2", plen2_32u4))
    costs: dict[str, Cost] = {}
    saved = os.environ.get("ROBOSCRIPT_FIRMWARE_CACHE")
    with tempfile.TemporaryDirectory() as cache:
        os.environ["ROBOSCRIPT_FIRMWARE_CACHE"] = cache
        try:
            costs["harness compile"] = _timed(harness)
            for name, recipe in recipes:
                costs[f"{name} cold build"] = _timed(lambda recipe=recipe: build(recipe()))
            costs["the three builds from the cache"] = _timed(
                lambda: [build(recipe()) for _, recipe in recipes]
            )
            if not quick:
                costs["whole tier, warm cache"] = _timed(_whole_tier)
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
    speeds = lockstep_speed(duration_s)
    rows = [
        info(
            "10",
            "emulated MIRTO firmware in lockstep (simulated s per CPU s)",
            speeds["lockstep cpu"],
            f"{duration_s:g} s of driving in 20 ms ticks, encoders turning; 16 MHz ATmega328P;"
            f" {speeds['lockstep wall']:.2f} simulated s per wall s at load average"
            f" {os.getloadavg()[0]:.1f}",
        ),
        info(
            "10",
            "lockstep ÷ free-running emulation, CPU (what the step round trips cost)",
            speeds["lockstep cpu"] / speeds["free cpu"],
            f"free-running {speeds['free cpu']:.2f} simulated s per CPU s",
        ),
    ]
    costs = tier_cost(quick)
    for name, cost in costs.items():
        rows.append(
            info(
                "10",
                f"firmware tier: {name} (CPU s)",
                cost.cpu_s,
                f"wall {cost.wall_s:.1f} s at load average {cost.load:.1f}",
                unit=" s",
            )
        )
    return rows


if __name__ == "__main__":
    run_alone(__doc__, measure, "1 s of lockstep, not 5 s")
