"""Shared pieces of the benchmark suite: result rows, the table, pinning, wire arithmetic.

Every benchmark reports a *ratio* against a limit or a baseline measured in the same run, so
the speed of the machine cancels out. A :class:`Row` carries that ratio, the goal it is held
to, and the absolute figures it was computed from (for the curious, not for judging).

This directory is not collected by pytest (its files are not named ``test_*.py``).
"""

from __future__ import annotations

import argparse
import contextlib
import datetime
import math
import os
import platform
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass

__all__ = [
    "BITS_PER_BYTE_8N1",
    "PINNING_NOTE",
    "WIRE_BAUD",
    "Row",
    "at_least",
    "at_most",
    "format_markdown",
    "format_table",
    "info",
    "machine_header",
    "percentile",
    "pinned_to_one_core",
    "wire_time_s",
]

WIRE_BAUD = 115200
"""The classroom serial rate every wire-limited figure is computed at, bits per second."""
BITS_PER_BYTE_8N1 = 10
"""8N1 framing: a start bit, 8 data bits and a stop bit per byte."""


def wire_time_s(n_bytes: float, baud: int = WIRE_BAUD) -> float:
    """Seconds that ``n_bytes`` take on a serial line at ``baud`` (8N1)."""
    return n_bytes * BITS_PER_BYTE_8N1 / baud


@dataclass(frozen=True)
class Row:
    """One line of the results table.

    Attributes:
        key: Which benchmark (1-7, as numbered in the README).
        name: What was measured.
        ratio: The measured ratio, or ``None`` for a row not measured yet.
        unit: How the ratio reads (``"×"`` for a multiple, ``"%"`` for a share of a core).
        goal: The target, as text (``">= 100×"``); empty for an informational row.
        passed: Whether the goal was met; ``None`` for an informational row.
        detail: The absolute figures behind the ratio.
    """

    key: str
    name: str
    ratio: float | None
    unit: str
    goal: str
    passed: bool | None
    detail: str

    @property
    def verdict(self) -> str:
        """``PASS``, ``MISS``, ``info`` or ``n/a`` (not measured)."""
        if self.ratio is None:
            return "n/a"
        if self.passed is None:
            return "info"
        return "PASS" if self.passed else "MISS"

    @property
    def ratio_text(self) -> str:
        """The ratio with a sensible number of digits."""
        if self.ratio is None:
            return "—"
        value = self.ratio
        if value == 0 or abs(value) >= 100:
            text = f"{value:,.0f}"
        elif abs(value) >= 10:
            text = f"{value:.1f}"
        elif abs(value) >= 0.1:
            text = f"{value:.2f}"
        else:
            text = f"{value:.4f}"
        return f"{text} {self.unit}".rstrip()


def at_least(key: str, name: str, ratio: float, goal: float, detail: str, unit: str = "×") -> Row:
    """A row whose ratio must reach ``goal``."""
    return Row(key, name, ratio, unit, f">= {goal:g} {unit}", ratio >= goal, detail)


def at_most(key: str, name: str, ratio: float, goal: float, detail: str, unit: str = "×") -> Row:
    """A row whose ratio must stay at or below ``goal``."""
    return Row(key, name, ratio, unit, f"<= {goal:g} {unit}", ratio <= goal, detail)


def info(key: str, name: str, ratio: float, detail: str, unit: str = "×") -> Row:
    """A row reported without a goal."""
    return Row(key, name, ratio, unit, "", None, detail)


def percentile(samples: Sequence[float], fraction: float) -> float:
    """The ``fraction`` quantile (0..1) of ``samples``, nearest rank (no interpolation)."""
    if not samples:
        return math.nan
    ordered = sorted(samples)
    index = min(len(ordered) - 1, max(0, math.ceil(fraction * len(ordered)) - 1))
    return ordered[index]


PINNING_NOTE = (
    "rows 1-3 run this process and its device process on one CPU (the idlest when each "
    "starts; performance.md D.6); rows 4-6 are not pinned"
)
"""What :func:`pinned_to_one_core` does, for table headers."""


@contextlib.contextmanager
def pinned_to_one_core() -> Iterator[int | None]:
    """Pin this process, and the device processes it forks meanwhile, to one CPU.

    Two processes that talk over a socket on one core hand over without a cross-core wake-up,
    which in a VM costs tens of microseconds and varies; on one core the loopback figures
    repeat within about 1 % (performance.md D.6). The core chosen is the least busy one, so
    other work on the machine disturbs the run least. Loops with no peer process (the
    scheduler, idle CPU, the simulator) are better left unpinned: the kernel can then wake
    them on whichever core is free.

    Yields:
        The CPU pinned to, or ``None`` where the platform cannot pin.
    """
    if not hasattr(os, "sched_setaffinity"):
        yield None
        return
    allowed = os.sched_getaffinity(0)
    busy = _busy_fractions(sorted(allowed))
    # Ties go to the last core: interrupts and housekeeping tend to land on CPU 0.
    core = min(sorted(allowed, reverse=True), key=lambda cpu: busy.get(cpu, 0.0))
    os.sched_setaffinity(0, {core})
    try:
        yield core
    finally:
        os.sched_setaffinity(0, allowed)


def _cpu_times() -> dict[int, tuple[int, int]]:
    """(busy, total) jiffies per CPU from /proc/stat; empty where there is no /proc."""
    times = {}
    try:
        with open("/proc/stat", encoding="ascii") as stat:
            for line in stat:
                name, *fields = line.split()
                if name.startswith("cpu") and name != "cpu":
                    values = [int(field) for field in fields]
                    idle = values[3] + values[4]  # idle + iowait
                    times[int(name[3:])] = (sum(values) - idle, sum(values))
    except (OSError, ValueError):
        return {}
    return times


def _busy_fractions(cpus: Sequence[int], window_s: float = 0.2) -> dict[int, float]:
    """Share of ``window_s`` each CPU spent busy (other processes on the machine)."""
    before = _cpu_times()
    time.sleep(window_s)
    after = _cpu_times()
    busy = {}
    for cpu in cpus:
        if cpu in before and cpu in after:
            total = after[cpu][1] - before[cpu][1]
            busy[cpu] = (after[cpu][0] - before[cpu][0]) / total if total else 0.0
    return busy


def _cpu_model() -> str:
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as cpuinfo:
            for line in cpuinfo:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine() or "unknown CPU"


def machine_header(pinning: str) -> list[str]:
    """Lines naming when and where the table was measured."""
    now = datetime.datetime.now().astimezone()
    implementation = platform.python_implementation()
    system = f"{platform.system()} {platform.release()}"
    return [
        f"date:    {now:%Y-%m-%d %H:%M %Z}",
        f"python:  {implementation} {platform.python_version()} ({sys.executable})",
        f"machine: {_cpu_model()}, {os.cpu_count()} cores, {system}",
        f"pinning: {pinning}",
    ]


def format_table(rows: Sequence[Row]) -> str:
    """The rows as an aligned plain-text table."""
    header = ("#", "benchmark", "ratio", "goal", "result", "measured")
    cells = [header] + [
        (row.key, row.name, row.ratio_text, row.goal or "—", row.verdict, row.detail)
        for row in rows
    ]
    widths = [max(len(cell[i]) for cell in cells) for i in range(len(header) - 1)]
    lines = []
    for index, cell in enumerate(cells):
        fixed = "  ".join(text.ljust(width) for text, width in zip(cell, widths, strict=False))
        lines.append(f"{fixed}  {cell[-1]}".rstrip())
        if index == 0:
            lines.append("-" * len(lines[0]))
    return "\n".join(lines)


def format_markdown(rows: Sequence[Row]) -> str:
    """The rows as a Markdown table (for the README)."""
    lines = [
        "| # | Benchmark | Ratio | Goal | Result | Measured |",
        "|---|---|---|---|---|---|",
    ]
    for row in rows:
        goal = (row.goal or "—").replace(">=", "≥").replace("<=", "≤")
        lines.append(
            f"| {row.key} | {row.name} | {row.ratio_text} | {goal} | {row.verdict} | {row.detail} |"
        )
    return "\n".join(lines)


def run_alone(doc: str, measure: Callable[[bool], list[Row]], quick_help: str) -> None:
    """A benchmark's own command line: ``--quick``, then print its rows as a table.

    Args:
        doc: The benchmark module's docstring; its first line describes the command.
        measure: The benchmark's ``measure(quick)``.
        quick_help: What ``--quick`` shortens.
    """
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help=quick_help)
    args = parser.parse_args()
    print(format_table(measure(args.quick)))
