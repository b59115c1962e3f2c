"""Reading /proc: every process found, each read whole, whatever its name and however it ends.

A student chooses its processes' names (the name of the file it runs, or ``prctl``), and may
choose one that looks like the fields after it in ``/proc/PID/stat``; on a loaded machine
processes end between being listed and being read. Neither may hide a process from the
grader, lend it another's parent or state, nor stop the walk.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest
from helpers import HANG_BOUND_S

from roboscript.grading import processes
from roboscript.grading.processes import (
    ProcessStat,
    parse_stat,
    read_stat,
    read_status,
    stats,
    statuses,
    uid_of,
)

needs_proc = pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs /proc")

ODD_NAME = b"a) (T 1\nb"
"""A process name with ``) (``, a newline, and what reads as a stopped state and parent 1 to a
reader that splits ``stat`` at the first ``)``."""


@contextmanager
def _oddly_named(tmp_path: Path) -> Iterator[int]:
    """A ``sleep`` started from a copy of its program named :data:`ODD_NAME` (Linux names a
    process after the file it runs); killed afterwards."""
    program = shutil.which("sleep")
    if program is None:
        pytest.skip("no sleep program to copy")
    copy = tmp_path / ODD_NAME.decode()
    shutil.copy(program, copy)
    child = subprocess.Popen(["sleep", "600"], executable=copy)
    try:
        deadline = time.monotonic() + HANG_BOUND_S  # a bound for a broken test only
        while not _runs(child.pid, copy):
            assert time.monotonic() < deadline, "never ran its program"
            time.sleep(0.01)
        yield child.pid
    finally:
        child.kill()
        child.wait(HANG_BOUND_S)


def _runs(pid: int, program: Path) -> bool:
    """True once process ``pid`` runs ``program`` (Python's fork has become its exec)."""
    try:
        return os.readlink(f"/proc/{pid}/exe") == os.path.realpath(program)
    except OSError:
        return False


@needs_proc
def test_a_process_named_with_parentheses_and_a_newline_is_read_whole(tmp_path: Path) -> None:
    with _oddly_named(tmp_path) as pid:
        found = read_stat(pid)
        assert found is not None
        assert found.name == ODD_NAME
        assert found.parent == os.getpid()
        assert found.state in ("R", "S")  # not the "T" its name holds


@needs_proc
def test_the_walk_finds_an_oddly_named_process_with_its_own_parent_and_user(
    tmp_path: Path,
) -> None:
    with _oddly_named(tmp_path) as pid:
        walked = dict(stats())
        assert walked[pid].name == ODD_NAME and walked[pid].parent == os.getpid()
        status = dict(statuses())[pid]
        assert status[b"PPid"] == str(os.getpid()).encode()
        assert uid_of(status) == os.getuid()
        assert (read_status(pid) or {}).get(b"PPid") == status[b"PPid"]


def test_a_stat_is_read_by_its_last_parenthesis() -> None:
    fields = b" S 77 1 1 0 -1 4194560 100 0 0 0 3 4 5 6 20 0 1 0 9 1 1\n"
    found = parse_stat(b"42 (" + ODD_NAME + b")" + fields)
    assert found == ProcessStat(
        name=ODD_NAME, state="S", parent=77, cpu_ticks=7, children_cpu_ticks=11
    )
    assert found.cpu_s == 7 / processes.TICKS_PER_S
    assert found.cpu_with_reaped_children_s == 18 / processes.TICKS_PER_S


@pytest.mark.parametrize(
    "text",
    [b"", b"42 (sleep", b"42 (sleep) S 77", b"42 sleep S 77 1", b"42 (x) S seven 1 1 1 1 1 1"],
    ids=["empty", "no closing parenthesis", "cut short", "no name", "not a number"],
)
def test_a_stat_cut_short_or_garbled_is_no_process(text: bytes) -> None:
    assert parse_stat(text) is None


def _fake_proc(root: Path) -> Path:
    """A /proc where process 12 is whole and the others ended or cannot be read mid-walk."""
    whole = b"12 (sh) S 1 12 12 0 -1 0 0 0 0 0 1 2 3 4 20 0 1 0 5 6 7\n"
    (root / "12").mkdir(parents=True)
    (root / "12" / "stat").write_bytes(whole)
    (root / "12" / "status").write_bytes(b"Name:\tsh\nState:\tS (sleeping)\nUid:\t7\t7\t7\t7\n")
    (root / "13").mkdir()  # ended between the listing and the reading: its files are gone
    (root / "14").mkdir()
    (root / "14" / "stat").write_bytes(b"14 (x) S")  # cut short
    (root / "15" / "stat").mkdir(parents=True)  # cannot be read
    (root / "15" / "status").mkdir()
    (root / "self").mkdir()  # not a process
    (root / "self" / "stat").write_bytes(whole)
    return root


def test_processes_that_end_or_cannot_be_read_mid_walk_are_left_out(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(processes, "_PROC", str(_fake_proc(tmp_path / "proc")))
    assert [(pid, found.name, found.parent) for pid, found in stats()] == [(12, b"sh", 1)]
    assert [(pid, uid_of(fields)) for pid, fields in sorted(statuses())] == [(12, 7)]
    assert read_stat(13) is None and read_status(13) is None
    assert read_stat(15) is None and read_status(15) is None


def test_without_proc_the_walk_finds_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(processes, "_PROC", str(tmp_path / "none"))
    assert list(stats()) == [] and list(statuses()) == []


def test_the_memory_a_process_holds_is_read_and_a_gone_process_reads_none() -> None:
    if not os.path.isdir("/proc/self"):
        pytest.skip("needs /proc")
    held = processes.memory_bytes(os.getpid())
    assert held is not None and 1024**2 < held < 64 * 1024**3, "this interpreter holds some MiB"
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    assert processes.memory_bytes(child.pid) is None
