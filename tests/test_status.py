"""The live status line: drawn on a terminal, absent when piped or with --json."""

from __future__ import annotations

import os
import pty
import subprocess
import sys

from helpers import HANG_BOUND_S, ROOT, run_cli


def _run_on_a_terminal(*args: str) -> str:
    """Run roboscript with its standard error on a pty; return what the terminal received."""
    master, slave = pty.openpty()
    proc = subprocess.Popen(
        [sys.executable, "-m", "roboscript", *args],
        stdin=subprocess.DEVNULL,
        stdout=subprocess.DEVNULL,
        stderr=slave,
        cwd=ROOT,
        env=dict(os.environ, PYTHONPATH=str(ROOT)),
    )
    os.close(slave)
    chunks = []
    while True:
        try:
            data = os.read(master, 65536)
        except OSError:
            break
        if not data:
            break
        chunks.append(data)
    proc.wait(timeout=HANG_BOUND_S)
    os.close(master)
    return b"".join(chunks).decode("utf-8", "replace")


def test_status_line_is_drawn_on_a_terminal() -> None:
    screen = _run_on_a_terminal("run", "missions/square.yaml", "--realtime", "--max-time", "1.2")
    assert "\r\x1b[K" in screen
    assert "side" in screen and "driving" in screen and "heading" in screen


def test_no_status_line_when_piped_or_json() -> None:
    piped = run_cli("run", "missions/square.yaml", "--realtime", "--max-time", "1")
    assert "\x1b[K" not in piped.stderr
    screen = _run_on_a_terminal("run", "missions/square.yaml", "--json", "--max-time", "1")
    assert "\x1b[K" not in screen
