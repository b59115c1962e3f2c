"""The fork server inside a jail: one pre-imported interpreter, one forked process per run.

:class:`roboscript.grading.sandbox.WarmJail` starts it jailed, once for several runs of the
same student's mission (the same files visible, the same limits), as::

    python -I -m roboscript.grading.jail_server CONTROL_FD SWEEP MODULE [WARM_ARG...]

It imports ``MODULE`` and calls its ``warm_up(*WARM_ARG)`` once, so that a run starts in a few
milliseconds instead of re-importing roboscript. Then, for each request read from the control
socket (``SOCK_SEQPACKET``: a JSON object ``{"argv": [...], "cwd": "..."}`` with the run's
standard output, standard error and passed descriptors attached), it forks a child that:

* becomes a session of its own, with the descriptors in place (passed ones from 3 on);
* sends its process id to the grader as kernel-checked credentials (the grader reads it in
  its own PID namespace: the process whose CPU time it may measure and which it may kill);
* runs ``MODULE.main(argv)`` and exits with its status.

When the child has ended, whoever ended it, the server ends every other process the run left
(``SWEEP``: ``uid`` kills every process of the jail's user but the server and its
ancestors, for jails whose user is the run's alone; ``group`` kills the run's process group,
for a fallback that shares the grader's user), empties its scratch folder (``TMPDIR``), and
only then tells the grader the run's exit status: a run's leftovers never meet the next run.

The server makes itself undumpable first, so a run (same user, its child) can neither trace
nor read it. A run can still kill it: the grader then starts a new jail for the next run.
"""

from __future__ import annotations

import array
import contextlib
import importlib
import json
import os
import shutil
import signal
import socket
import struct
import sys
from collections.abc import Sequence

from roboscript.grading.processes import kill_user_processes, read_stat, reap_children

__all__ = ["main"]

_MAX_REQUEST = 1 << 16
_MAX_FDS = 16
_FIRST_PASSED_FD = 3
_HIGH_FD = 64
"""Received descriptors are moved above this before being put in place (no clash)."""


def main(argv: Sequence[str] | None = None) -> int:
    """Serve runs until the grader closes the control socket."""
    args = list(sys.argv[1:] if argv is None else argv)
    control_fd, sweep, module_name = int(args[0]), args[1], args[2]
    scratch = os.environ.get("TMPDIR", "/tmp")
    control = socket.socket(fileno=control_fd)
    _undumpable()
    module = importlib.import_module(module_name)
    with contextlib.suppress(Exception):  # a run reports its own problems better
        module.warm_up(*args[3:])
    control.send(json.dumps({"ready": os.getpid()}).encode())
    while True:
        request = _receive(control)
        if request is None:
            return 0
        message, fds = request
        status = _serve_one(control, module, message, fds, sweep, scratch)
        control.send(json.dumps({"status": status}).encode())


def _receive(control: socket.socket) -> tuple[dict[str, object], list[int]] | None:
    fds = array.array("i")
    data, ancillary, _flags, _addr = control.recvmsg(
        _MAX_REQUEST, socket.CMSG_LEN(_MAX_FDS * fds.itemsize)
    )
    for level, kind, payload in ancillary:
        if level == socket.SOL_SOCKET and kind == socket.SCM_RIGHTS:
            fds.frombytes(payload[: len(payload) - (len(payload) % fds.itemsize)])
    if not data:
        for fd in fds:
            os.close(fd)
        return None
    return json.loads(data), list(fds)


def _serve_one(
    control: socket.socket,
    module: object,
    message: dict[str, object],
    fds: list[int],
    sweep: str,
    scratch: str,
) -> int:
    argv = [str(a) for a in message.get("argv", [])]  # type: ignore[attr-defined]
    cwd = str(message.get("cwd", "/"))
    pid = os.fork()
    if pid == 0:  # the run
        code = 70
        try:
            code = _child(control, module, argv, cwd, fds)
        finally:
            os._exit(code)
    for fd in fds:
        os.close(fd)
    _, wait_status = os.waitpid(pid, 0)
    if sweep == "uid":  # the jail's user is the run's alone
        kill_user_processes(os.getuid(), _ancestors())
    else:
        with contextlib.suppress(OSError):
            os.killpg(pid, signal.SIGKILL)
    reap_children()
    _empty(scratch)
    return os.waitstatus_to_exitcode(wait_status)


def _child(
    control: socket.socket, module: object, argv: list[str], cwd: str, fds: list[int]
) -> int:
    os.setsid()
    signal.signal(signal.SIGCHLD, signal.SIG_DFL)
    # Kernel-checked: the grader reads this pid translated into its own PID namespace.
    credentials = struct.pack("3i", os.getpid(), os.getuid(), os.getgid())
    control.sendmsg(
        [b'{"started": true}'], [(socket.SOL_SOCKET, socket.SCM_CREDENTIALS, credentials)]
    )
    control.close()  # before the descriptors move: its number may be one of theirs
    import fcntl  # POSIX only; the grader imports this module on every system

    high = [fcntl.fcntl(fd, fcntl.F_DUPFD, _HIGH_FD) for fd in fds]
    out, err, *passed = high
    os.dup2(out, 1)
    os.dup2(err, 2)
    for i, fd in enumerate(passed):
        os.dup2(fd, _FIRST_PASSED_FD + i, inheritable=False)
    # Nothing else of the server's stays open in the run.
    os.closerange(_FIRST_PASSED_FD + len(passed), max(high) + 1)
    os.chdir(cwd)
    sys.argv = [str(getattr(module, "__file__", "")), *argv]
    sys.stdout = open(1, "w", encoding="utf-8", errors="backslashreplace", closefd=False)  # noqa: SIM115
    sys.stderr = open(2, "w", encoding="utf-8", errors="backslashreplace", closefd=False)  # noqa: SIM115
    try:
        code = module.main(argv)  # type: ignore[attr-defined]
    except SystemExit as exc:
        code = exc.code if isinstance(exc.code, int) else 1
    except BaseException:  # noqa: BLE001 - as the interpreter would: print it, exit 1
        import traceback

        traceback.print_exc()
        code = 1
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()
    return int(code or 0)


def _ancestors() -> set[int]:
    """This process and every process above it (in this PID namespace)."""
    found = {os.getpid()}
    pid = os.getppid()
    while pid > 0 and pid not in found:
        found.add(pid)
        stat = read_stat(pid)
        if stat is None:
            break
        pid = stat.parent
    return found


def _empty(scratch: str) -> None:
    """Remove what the run wrote in the scratch folder (read-only files shown there stay)."""
    try:
        entries = os.listdir(scratch)
    except OSError:
        return
    for name in entries:
        path = os.path.join(scratch, name)
        if os.path.isdir(path) and not os.path.islink(path):
            shutil.rmtree(path, ignore_errors=True)
        else:
            with contextlib.suppress(OSError):
                os.unlink(path)


def _undumpable() -> None:
    """Forbid tracing this process and reading its memory to anyone without privileges."""
    if sys.platform != "linux":
        return
    import ctypes

    pr_set_dumpable = 4
    with contextlib.suppress(OSError, AttributeError):
        ctypes.CDLL(None, use_errno=True).prctl(pr_set_dumpable, 0, 0, 0, 0)


if __name__ == "__main__":
    sys.exit(main())
