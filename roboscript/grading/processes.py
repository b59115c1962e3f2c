"""The processes of a jail's own user: found in ``/proc``, killed, reaped (Linux).

Used by the grader (:mod:`roboscript.grading.sandbox`) and by the fork server inside a jail
(:mod:`roboscript.grading.jail_server`), which imports nothing else of the grader's: standard
library only, so a jail starts without importing the sandbox that started it.
"""

from __future__ import annotations

import contextlib
import os
import signal
from collections.abc import Collection, Iterator

__all__ = ["kill_user_processes", "live_processes", "reap_children", "statuses", "uid_of"]

_SWEEP_ROUNDS = 1000


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
    """Every process in ``/proc`` with the fields of its ``status`` file (Linux)."""
    for name in os.listdir("/proc"):
        if not name.isdigit():
            continue
        try:
            with open(f"/proc/{name}/status", "rb") as handle:
                status = handle.read()
        except OSError:
            continue  # it ended meanwhile
        lines = status.splitlines()
        yield int(name), dict(line.split(b":\t", 1) for line in lines if b":\t" in line)


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
