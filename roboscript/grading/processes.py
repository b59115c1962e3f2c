"""Processes as Linux tells them in ``/proc``: read, walked, killed, reaped.

Every reading of ``/proc`` the grader makes is here, once: the walk over every process
(:func:`statuses`, :func:`stats`), a process's ``stat`` (:func:`read_stat`: parent, state, CPU
time) and the children each of its threads started (:func:`listed_children`). The walk is
robust to what a machine under load and a hostile student do to it: a process that ends
between being listed and being read, an entry that cannot be read or is cut short, and a
process name (which a student chooses: ``prctl(PR_SET_NAME)``, or the name of the file it
runs) holding spaces, parentheses or a newline, which ``stat`` shows as they are.

Used by the grader (:mod:`roboscript.grading.sandbox`, :mod:`roboscript.grading.cpu_time`) and
by the fork server inside a jail (:mod:`roboscript.grading.jail_server`), which imports nothing
else of the grader's: standard library only, so a jail starts without importing the sandbox
that started it.
"""

from __future__ import annotations

import contextlib
import os
import signal
from collections.abc import Callable, Collection, Iterator
from typing import NamedTuple, TypeVar

__all__ = [
    "CHILDREN_LISTED",
    "TICKS_PER_S",
    "ProcessStat",
    "kill_user_processes",
    "listed_children",
    "live_processes",
    "parse_stat",
    "read_stat",
    "read_status",
    "reap_children",
    "stats",
    "statuses",
    "uid_of",
    "waited_s",
]

_PROC = "/proc"
_SWEEP_ROUNDS = 1000

TICKS_PER_S = float(os.sysconf("SC_CLK_TCK")) if hasattr(os, "sysconf") else 100.0
"""Clock ticks per second, the unit of the CPU times in ``/proc/PID/stat``."""

CHILDREN_LISTED = os.path.exists(f"{_PROC}/{os.getpid()}/task/{os.getpid()}/children")
"""Whether Linux lists each thread's children (``CONFIG_PROC_CHILDREN``, on in the common
distributions' kernels)."""

_T = TypeVar("_T")


class ProcessStat(NamedTuple):
    """What the grader reads of a process's ``/proc/PID/stat``.

    Attributes:
        name: The process's name as the kernel keeps it (at most 15 bytes, chosen by the
            process: spaces, parentheses and newlines included).
        state: One letter: ``R`` running, ``S`` sleeping, ``T`` stopped, ``t`` stopped by a
            tracer, ``Z`` ended but not reaped, ...
        parent: The parent's process id.
        cpu_ticks: CPU time the process used itself, user and system, in clock ticks
            (:data:`TICKS_PER_S`).
        children_cpu_ticks: CPU time of its children it has reaped, user and system, in clock
            ticks.
    """

    name: bytes
    state: str
    parent: int
    cpu_ticks: int
    children_cpu_ticks: int

    @property
    def cpu_s(self) -> float:
        """CPU seconds the process used itself, user and system."""
        return self.cpu_ticks / TICKS_PER_S

    @property
    def cpu_with_reaped_children_s(self) -> float:
        """CPU seconds the process and the children it has reaped used, user and system."""
        return (self.cpu_ticks + self.children_cpu_ticks) / TICKS_PER_S


def parse_stat(text: bytes) -> ProcessStat | None:
    """The fields of a ``/proc/PID/stat`` file's ``text``; None if it is cut short or not one.

    The name (the second field, in parentheses) may itself hold spaces, parentheses and
    newlines: it ends at the *last* ``)``, since no field after it holds one.
    """
    opened, closed = text.find(b"("), text.rfind(b")")
    if opened < 0 or closed < opened:
        return None
    fields = text[closed + 1 :].split()
    try:
        return ProcessStat(
            name=text[opened + 1 : closed],
            state=fields[0].decode("ascii"),
            parent=int(fields[1]),
            cpu_ticks=int(fields[11]) + int(fields[12]),
            children_cpu_ticks=int(fields[13]) + int(fields[14]),
        )
    except (IndexError, ValueError):  # UnicodeDecodeError is a ValueError
        return None


def read_stat(pid: int) -> ProcessStat | None:
    """Process ``pid``'s ``stat``; None if it has ended (or its entry cannot be read)."""
    text = _read(pid, "stat")
    return None if text is None else parse_stat(text)


def stats() -> Iterator[tuple[int, ProcessStat]]:
    """Every process in ``/proc`` with its ``stat`` (Linux; none where there is no ``/proc``)."""
    return _each("stat", parse_stat)


def waited_s(pid: int) -> float | None:
    """Seconds the main thread of ``pid`` spent waiting for a CPU (runnable, but another
    program had it), from Linux's scheduler statistics; None if it ended or is not told."""
    text = _read(pid, "schedstat")
    try:
        return int((text or b"").split()[1]) / 1e9
    except (ValueError, IndexError):
        return None


def memory_bytes(pid: int) -> int | None:
    """Memory ``pid`` holds, in bytes: its share of every page it uses (a page shared by ``n``
    processes counts ``1/n`` in each, so a tree's shares add up to what it holds; Linux 4.14
    and later), else its resident pages; None if it has ended."""
    text = _read(pid, "smaps_rollup")
    for line in (text or b"").splitlines():
        if line.startswith(b"Pss:"):
            try:
                return int(line.split()[1]) * 1024
            except (IndexError, ValueError):
                break
    text = _read(pid, "statm")
    try:
        return int((text or b"").split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (IndexError, ValueError, OSError):
        return None


def listed_children(pid: int) -> list[int]:
    """The children each thread of ``pid`` started, as Linux lists them (where
    :data:`CHILDREN_LISTED`): a child's parent is the thread that started it, not its
    process's main thread. Empty if ``pid`` has ended."""
    children: list[int] = []
    try:
        threads = os.listdir(f"{_PROC}/{pid}/task")
    except OSError:
        return children
    for thread in threads:
        text = _read(pid, f"task/{thread}/children")
        try:
            children.extend(int(child) for child in (text or b"").split())
        except ValueError:
            continue
    return children


def kill_user_processes(uid: int, keep: Collection[int] = ()) -> bool:
    """Kill every live process of ``uid`` but those in ``keep``, until none is left.

    For a user that is one jail's alone: what it runs is exactly what its runs left. A fork
    bomb runs out of processes (its limit is small) before this runs out of rounds.

    Returns:
        True when none is left.
    """
    for _ in range(_SWEEP_ROUNDS):
        victims = [pid for pid in live_processes(uid) if pid not in keep]
        if not victims:
            return True
        for pid in victims:
            with contextlib.suppress(OSError):
                os.kill(pid, signal.SIGKILL)
        reap_children()
    return False


def live_processes(uid: int) -> list[int]:
    """The processes of ``uid`` that have not ended (zombies excluded)."""
    return [
        pid
        for pid, fields in statuses()
        if uid_of(fields) == uid and not fields.get(b"State", b"Z").startswith((b"Z", b"X"))
    ]


def statuses() -> Iterator[tuple[int, dict[bytes, bytes]]]:
    """Every process in ``/proc`` with the fields of its ``status`` file (Linux; none where
    there is no ``/proc``). The kernel writes a name's newline there as ``\\n``: one field
    a line."""
    return _each("status", _parse_status)


def read_status(pid: int) -> dict[bytes, bytes] | None:
    """The fields of process ``pid``'s ``status`` file (``{b"Uid": b"0\t0\t0\t0", ...}``);
    None if it has ended (or its entry cannot be read)."""
    text = _read(pid, "status")
    return None if text is None else _parse_status(text)


def _parse_status(text: bytes) -> dict[bytes, bytes]:
    return dict(line.split(b":\t", 1) for line in text.splitlines() if b":\t" in line)


def _each(file: str, parse: Callable[[bytes], _T | None]) -> Iterator[tuple[int, _T]]:
    """Every process in ``/proc`` with its ``file`` parsed: the one walk. A process that ends
    between being listed and being read, or whose file cannot be read or parsed, is left out."""
    try:
        names = os.listdir(_PROC)
    except OSError:  # no /proc: macOS, Windows
        return
    for name in names:
        if not name.isdigit():
            continue
        text = _read(int(name), file)
        parsed = None if text is None else parse(text)
        if parsed is not None:
            yield int(name), parsed


def _read(pid: int, file: str) -> bytes | None:
    """The bytes of ``/proc/PID/FILE``; None if the process has ended or the file cannot be
    read (another user's, where ``/proc`` hides them)."""
    try:
        with open(f"{_PROC}/{pid}/{file}", "rb") as handle:
            return handle.read()
    except OSError:
        return None


def uid_of(fields: dict[bytes, bytes]) -> int:
    """The real user id in a ``status`` file's fields (-1 if missing)."""
    return int(fields.get(b"Uid", b"-1").split()[0])


def reap_children() -> None:
    """Reap this process's ended children, without waiting for any."""
    while True:
        try:
            pid, _status = os.waitpid(-1, os.WNOHANG)
        except ChildProcessError:
            return
        if pid == 0:
            return
