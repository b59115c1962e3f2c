"""Faults: lost links, silent robots, garbage, refusals, Ctrl-C, bad files.

Real processes and loopback sockets, as a classroom would meet them. Nothing may hang, print a
traceback, or leave a motor running.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest
from fake_asip import FakeAsipBoard
from helpers import HANG_BOUND_S, ROOT, run_cli

from roboscript.transport.wirelog import read_wire_log

SHORT = """
states:
  settle:
    do: {wait: {duration: 0.3 s}}
    on: {done: beep}
  beep:
    do: {play_tone: {frequency: 440 Hz, duration: 0.2 s}}
    on: {done: linger, failed: refused}
  linger:
    do: {wait: {duration: 1.5 s}}
    on: {done: end}
  refused: {final: failure}
  end: {final: success}
"""


@pytest.fixture
def mission(write_mission: Callable[..., Path]) -> Path:
    return write_mission(SHORT)


def _one_sentence(stderr: str) -> str:
    lines = [line for line in stderr.strip().splitlines() if not line.startswith("roboscript:")]
    assert "Traceback" not in stderr
    return lines[-1]


def test_well_behaved_board_completes(mission: Path) -> None:
    board = FakeAsipBoard()
    try:
        result = run_cli("run", str(mission), "--port", board.url, "--quiet")
    finally:
        board.close()
    assert result.returncode == 0, result.stderr
    assert b"T,P,440,200\n" in board.received


def test_disconnect_mid_mission_ends_with_one_sentence_and_a_complete_wire_log(
    mission: Path, tmp_path: Path
) -> None:
    board = FakeAsipBoard(close_after_s=1.0)
    log = tmp_path / "wire.log"
    try:
        result = run_cli("run", str(mission), "--port", board.url, "--wire-log", str(log))
    finally:
        board.close()
    assert result.returncode == 1
    assert _one_sentence(result.stderr).startswith(
        f"error: the connection to {board.url} was lost "
    )
    assert _one_sentence(result.stderr).endswith(" s after connecting")
    received = b"".join(data for _, d, data in read_wire_log(log) if d == "<")
    assert received == bytes(board.sent)


def test_silent_robot_is_stopped_and_the_mission_fails(mission: Path) -> None:
    board = FakeAsipBoard(silent_after_s=0.6)
    try:
        result = run_cli("run", str(mission), "--port", board.url)
        time.sleep(0.1)
    finally:
        board.close()
    assert result.returncode == 1
    assert _one_sentence(result.stderr).startswith("error: the robot stopped responding")
    after_silence = bytes(board.received).rsplit(b"T,P,440,200\n", 1)[-1]
    assert b"M,S,0\n" in after_silence  # the stop went out while the link was writable


def test_garbage_is_skipped_counted_and_reported_once_per_kind(mission: Path) -> None:
    board = FakeAsipBoard(garbage=True)
    try:
        result = run_cli("run", str(mission), "--port", board.url)
    finally:
        board.close()
    assert result.returncode == 0, result.stderr
    warnings = [line for line in result.stderr.splitlines() if "cannot read" in line]
    kinds = {line.split("(")[1].split(":")[0] for line in warnings}
    assert len(warnings) == len(kinds) >= 2  # each kind once, however often it came


def test_board_refusal_fails_the_action_with_the_boards_reason(mission: Path) -> None:
    board = FakeAsipBoard(refuse_tones=True)
    try:
        result = run_cli("run", str(mission), "--port", board.url)
    finally:
        board.close()
    assert result.returncode == 1
    assert _one_sentence(result.stderr) == (
        "failure: ended in the failure state 'refused' after play_tone failed in state 'beep':"
        " the board refused 'T,P': the service does not know that request"
    )


def _start_realtime(mission: Path, log: Path) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [
            sys.executable,
            "-m",
            "roboscript",
            "run",
            str(mission),
            "--realtime",
            "--wire-log",
            str(log),
        ],
        cwd=ROOT,
        env=dict(os.environ, PYTHONPATH=str(ROOT)),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def _wait_for_state(proc: subprocess.Popen[str], name: str) -> None:
    """Read the run's progress until it enters state ``name`` (a signal sent while it still
    starts up, as a busy machine may make it, would test something else)."""
    assert proc.stderr is not None
    for line in proc.stderr:  # progress lines go to stderr, flushed as states are entered
        if name in line.split():
            return
    pytest.fail(f"the run ended before entering {name!r}")


def test_ctrl_c_stops_the_robot_before_exiting_130(tmp_path: Path) -> None:
    log = tmp_path / "wire.log"
    proc = _start_realtime(ROOT / "missions" / "square.yaml", log)
    _wait_for_state(proc, "side")  # the mission is under way: the wheels are turning
    proc.send_signal(signal.SIGINT)
    _, stderr = proc.communicate(timeout=HANG_BOUND_S)
    assert proc.returncode == 130
    assert "Traceback" not in stderr
    sent = [data for _, d, data in read_wire_log(log) if d == ">"]
    assert b"M,S,0\n" in sent[-3:]
    assert sent[-1] == b"M,M,0,0\n"


def test_a_second_ctrl_c_still_exits(tmp_path: Path) -> None:
    proc = _start_realtime(ROOT / "missions" / "square.yaml", tmp_path / "w.log")
    _wait_for_state(proc, "side")
    proc.send_signal(signal.SIGINT)
    proc.send_signal(signal.SIGINT)
    proc.communicate(timeout=HANG_BOUND_S)
    assert proc.returncode == 130


@pytest.mark.parametrize(
    ("option", "content", "expected"),
    [
        (
            "--robot",
            "extends: mirto\ntrack_mm: -3\n",
            "F:2:1: error: 'track_mm' must be a positive number",
        ),
        ("--robot", "extends: mirt\n", "F:1:1: error: 'extends' must name a built-in robot"),
        ("--world", "walls:\n  - box: {x: 0}\n", "F:2:10: error: a box needs 'y'"),
    ],
)
def test_bad_profile_or_world_file_is_exit_2_with_a_location(
    tmp_path: Path, option: str, content: str, expected: str
) -> None:
    path = tmp_path / "f.yaml"
    path.write_text(content, encoding="utf-8")
    result = run_cli("run", "missions/square.yaml", option, str(path))
    assert result.returncode == 2
    assert "Traceback" not in result.stderr
    assert result.stderr.strip().replace(str(path), "F").startswith(expected)


def test_a_bad_option_in_a_profile_file_is_invalid_input_on_the_simulator(
    tmp_path: Path,
) -> None:
    profile = tmp_path / "rover.yaml"
    profile.write_text("extends: stackmod-rover\noptions: {motor_address: 7}\n", encoding="utf-8")
    result = run_cli("run", "missions/square.yaml", "--robot", str(profile))
    assert result.returncode == 2
    assert result.stderr.startswith("error: rover: option 'motor_address' must be one character")
    assert "Traceback" not in result.stderr
