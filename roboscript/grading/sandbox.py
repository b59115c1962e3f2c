"""The sandbox a student's code runs in: one untrusted process tree, started jailed.

On Linux the jail is Debian's ``bubblewrap`` (``bwrap``), a maintained namespace tool, not a
home-made one: no network, a read-only view of the system with only the interpreter, the
roboscript package and the files the grader names, a private size-capped ``/tmp``, and a PID
namespace of its own, so every process the student starts dies with the jail. Hard resource
limits (soft = hard, so they cannot be lifted) bound memory, CPU time, processes and file size;
standard output and error go to pipes the caller drains, capped.

As root (CI, containers) the student's processes run as a uid of their own, never root, so that
the process limit is enforced, is not shared with other jails running at the same time, and no
signal reaches the grader's processes. Where ``bwrap`` is missing or cannot run (macOS,
Windows, a container that forbids namespaces) :func:`detect_isolation` says so in one line and
:class:`Jail` falls back to a separate process with resource limits only. What each platform
guarantees is in ``docs/teachers/grading.md`` ("What the sandbox guarantees").
"""

from __future__ import annotations

import array
import contextlib
import functools
import json
import os
import select
import shutil
import signal
import site
import socket
import stat
import struct
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from roboscript.grading.processes import (
    kill_user_processes,
    read_stat,
    read_status,
    reap_children,
    statuses,
    uid_of,
)
from roboscript.interrupts import RUN_USER_ALONE

if TYPE_CHECKING:
    from typing_extensions import Self

if sys.platform != "win32":
    import resource

__all__ = [
    "Isolation",
    "Jail",
    "JailedRun",
    "Limits",
    "WarmJail",
    "byte_compile_package",
    "check_visible",
    "detect_isolation",
    "kill_user_processes",
    "private_class",
    "process_cpu_time_s",
    "reap_children",
    "warm_jails_supported",
]

_PACKAGE = Path(__file__).resolve().parent.parent
# An editable install: the package sits in the git checkout beside the teachers' hidden tests.
_CHECKOUT = _PACKAGE.parent if (_PACKAGE.parent / "pyproject.toml").is_file() else None

_JAIL_UID_BASE = 0x7000_0000
"""Jails started by root run as ``base + 16 * grader pid + n``: systemd leaves this range
unused, and a uid per jail keeps one jail's processes from counting against another's limit."""
_UIDS_PER_PROCESS = 16

_SYSTEM_DIRS = ("/usr", "/bin", "/sbin", "/lib", "/lib32", "/lib64", "/libx32")
_SYSTEM_FILES = ("/etc/ld.so.cache", "/etc/ld.so.conf", "/etc/ld.so.conf.d", "/etc/localtime")
_NEVER_BOUND = ("/", "/proc", "/dev", "/tmp")
_BASE_ENV = {
    "HOME": "/tmp",
    "TMPDIR": "/tmp",
    "PATH": "/usr/bin:/bin",
    "LANG": "C.UTF-8",
    "PYTHONDONTWRITEBYTECODE": "1",
}
_READ_CHUNK = 1 << 16
_READS_PER_DRAIN = 16
"""At most this many chunks per stream per :meth:`Jail.drain`: a flood cannot starve the
caller's loop."""
_START_TIMEOUT_S = 10.0
_TEARDOWN_TIMEOUT_S = 10.0
_POLL_STEP_S = 0.01
_REMEDY_LINUX = "install it (apt install bubblewrap) for full isolation"
_LIMITS_ONLY = (
    "students' code runs with resource limits only and can read any file this user can read"
)


@dataclass(frozen=True)
class Limits:
    """Resource limits of one jail; every limit is hard (the student cannot raise it).

    Attributes:
        memory_bytes: Address space of each process, in bytes (``RLIMIT_AS``).
        cpu_time_s: CPU time of each process, in seconds (``RLIMIT_CPU``).
        processes: Processes and threads the student may have at once, the first included
            (``RLIMIT_NPROC``).
        file_size_bytes: Largest file a process may write, in bytes (``RLIMIT_FSIZE``).
        scratch_bytes: Size of the private writable ``/tmp``, in bytes (bubblewrap only).
        output_bytes: Bytes kept of standard output and of standard error, each; the rest is
            counted and dropped.
        total_memory_bytes: Memory all of a run's processes may hold together, in bytes: the
            world reads it four times a second and ends a run over it (``memory_bytes`` is
            each process's alone, and ``processes`` of them could hold that many times more).
    """

    memory_bytes: int = 1024**3
    cpu_time_s: int = 120
    processes: int = 32
    file_size_bytes: int = 16 * 1024**2
    scratch_bytes: int = 64 * 1024**2
    output_bytes: int = 64 * 1024
    total_memory_bytes: int = 2 * 1024**3

    def __post_init__(self) -> None:
        for name, value in vars(self).items():
            if not isinstance(value, int) or value < 1:
                raise ValueError(f"Limits.{name} must be a positive whole number, not {value!r}")


BUBBLEWRAP = "bubblewrap"
SEPARATE_USER = "separate user"
LIMITS_ONLY = "resource limits only"
PROCESS_ONLY = "separate process only"
ISOLATION_VARIABLE = "ROBOSCRIPT_ISOLATION"
"""Forces the isolation (``bubblewrap``, ``user`` or ``limits``) when it is available; for
tests, and for a teacher who wants to see what a weaker mode does."""
_FORCED = {"bubblewrap": BUBBLEWRAP, "user": SEPARATE_USER, "limits": LIMITS_ONLY}


@dataclass(frozen=True)
class Isolation:
    """How students' code is isolated on this computer.

    Attributes:
        name: :data:`BUBBLEWRAP` (a full jail), :data:`SEPARATE_USER` (no bubblewrap, but the
            grader is root: each jail runs as a user of its own), or what the fallback offers
            (:data:`LIMITS_ONLY`, :data:`PROCESS_ONLY`).
        complete: True only when bubblewrap's full isolation is in force.
        warning: One line to print when not complete (``""`` when complete).
    """

    name: str
    complete: bool
    warning: str

    @property
    def separate_user(self) -> bool:
        """True when each jail runs as a user of its own without bubblewrap."""
        return self.name == SEPARATE_USER

    @property
    def statement(self) -> str:
        """One sentence for every report: how the students' runs were isolated."""
        if self.complete:
            return (
                "each run was sandboxed by bubblewrap: it saw only its own files and a"
                " read-only system, with no network, its own processes only and hard limits"
            )
        if self.separate_user:
            return (
                "each run ran as a user of its own with hard limits (bubblewrap cannot run"
                " here): the tests, classmates' files and reports were unreadable to it, but"
                " it could reach the network and see other processes"
            )
        return f"students' runs were not isolated: {self.warning}"


_AS_ROOT = (
    "students' code runs as root, with limits it can lift, and can read any file and signal"
    " any process"
)
_AS_USER = (
    "each run is a user of its own with hard limits, and cannot read the tests, classmates'"
    " files or reports, but can reach the network and see other processes"
)


def _fallback(why: str, offer: str = "", remedy: str = _REMEDY_LINUX) -> Isolation:
    root = os.name == "posix" and os.geteuid() == 0
    if not offer and root and sys.platform == "linux" and _forced() != LIMITS_ONLY:
        problem = _probe_user()
        if not problem:
            return Isolation(SEPARATE_USER, False, f"{why}: {_AS_USER}; {remedy}")
        why += f", and a run as a user of its own cannot start ({problem})"
    if not offer:
        offer = _AS_ROOT if root else _LIMITS_ONLY
    name = LIMITS_ONLY if sys.platform != "win32" else PROCESS_ONLY
    return Isolation(name, False, f"{why}: {offer}; {remedy}")


def _forced() -> str:
    return _FORCED.get(os.environ.get(ISOLATION_VARIABLE, "").strip().lower(), "")


@functools.cache
def detect_isolation() -> Isolation:
    """The isolation :class:`Jail` gives here, found once per process.

    Bubblewrap counts only when ``bwrap`` is on ``PATH`` and a quick probe (the interpreter
    started jailed, as :class:`Jail` would) succeeds. Without it, a grader running as root on
    Linux runs each jail as a user of its own (:data:`SEPARATE_USER`). The environment
    variable :data:`ISOLATION_VARIABLE` can ask for a weaker mode than the best available.

    Returns:
        The isolation; when it is not complete its ``warning`` says why and what to do.
    """
    forced = _forced()
    if forced in (SEPARATE_USER, LIMITS_ONLY):
        return _fallback(
            f"{ISOLATION_VARIABLE} asks for '{forced}'",
            remedy=f"unset {ISOLATION_VARIABLE} for the best isolation available",
        )
    if sys.platform == "win32":
        return _fallback(
            "bubblewrap (bwrap) does not exist on Windows",
            "students' code runs in a separate process with no resource limits and can read"
            " any file this user can read",
            "grade on Linux with bubblewrap for full isolation",
        )
    if sys.platform != "linux":
        system = "macOS" if sys.platform == "darwin" else sys.platform
        return _fallback(
            f"bubblewrap (bwrap) does not exist on {system}",
            remedy="grade on Linux with bubblewrap for full isolation",
        )
    if shutil.which("bwrap") is None:
        return _fallback("bubblewrap (bwrap) is not installed")
    if os.geteuid() == 0 and shutil.which("setpriv") is None:
        return _fallback(
            "setpriv (util-linux), which bubblewrap needs when the grader runs as root, is not"
            " installed",
            remedy="install it (apt install util-linux) for full isolation",
        )
    problem = _probe()
    if problem:
        return _fallback(
            f"bubblewrap (bwrap) does not run here ({problem})",
            remedy="allow it to create namespaces (see docs/teachers/grading.md) for full"
            " isolation",
        )
    return Isolation(BUBBLEWRAP, True, "")


def _probe_user() -> str:
    """Start the interpreter as a jail's own user once; what went wrong, or ``""``.

    Without bubblewrap that user must reach the interpreter and roboscript itself: an
    interpreter under a folder only root may enter (``/root``) cannot start.
    """
    user = _jail_uid()
    try:
        done = subprocess.run(
            [sys.executable, "-I", "-c", "import roboscript.grading.jail_server"],
            stdin=subprocess.DEVNULL,
            capture_output=True,
            cwd="/",
            env=dict(_BASE_ENV),
            user=user,
            group=user,
            extra_groups=[],
            timeout=_START_TIMEOUT_S * 6,
            check=False,
        )
    except (OSError, subprocess.SubprocessError) as exc:
        return f"{sys.executable}: {exc.strerror or exc}" if isinstance(exc, OSError) else str(exc)
    finally:
        kill_user_processes(user)
    if done.returncode == 0:
        return ""
    lines = done.stderr.decode("utf-8", "replace").strip().splitlines()
    return (lines[-1] if lines else f"exit status {done.returncode}")[:120]


def _probe() -> str:
    """Start the interpreter jailed once; the first line of what went wrong, or ``""``."""
    argv = [sys.executable, "-I", "-S", "-c", ""]
    try:
        plan = _bubblewrap_plan(argv, (), Path("/"), {}, Limits(), None)
        done = subprocess.run(
            plan.argv,
            stdin=subprocess.DEVNULL,
            capture_output=True,
            cwd="/",
            env=dict(_BASE_ENV),
            preexec_fn=plan.preexec,
            timeout=_START_TIMEOUT_S,
            check=False,
        )
    except (OSError, subprocess.SubprocessError, ValueError) as exc:
        return str(exc).splitlines()[0][:120] if str(exc) else type(exc).__name__
    if done.returncode == 0:
        return ""
    lines = done.stderr.decode("utf-8", "replace").strip().splitlines()
    return (lines[0] if lines else f"exit status {done.returncode}")[:120]


@functools.cache
def byte_compile_package() -> bool:
    """Write the roboscript package's compiled modules beside it, once per grader process.

    A jail cannot write ``.pyc`` files (and ``PYTHONDONTWRITEBYTECODE`` forbids it anyway), so
    an install that was never compiled (an editable install, ``pip install --no-compile``)
    would compile every module from source at the start of every run, on the student's time.
    Installs from a wheel are compiled by pip already; then this only checks timestamps.

    Returns:
        True when every module has an up-to-date compiled file (False: the package folder is
        not writable here and some are missing; runs still work, each compiling what it
        imports).
    """
    import compileall

    return bool(compileall.compile_dir(str(_PACKAGE), quiet=2, workers=1))


# ----------------------------------------------------------------------------------- output


class _Capped:
    """The first ``limit`` bytes of a stream, and how many more were dropped."""

    def __init__(self, limit: int) -> None:
        self.limit = limit
        self.kept = bytearray()
        self.dropped = 0

    def feed(self, data: bytes) -> None:
        room = self.limit - len(self.kept)
        if room > 0:
            self.kept += data[:room]
        self.dropped += max(0, len(data) - max(room, 0))

    def text(self) -> str:
        text = self.kept.decode("utf-8", "replace")
        if self.dropped:
            newline = "" if not text or text.endswith("\n") else "\n"
            text += f"{newline}… (cut: {self.dropped} more bytes)\n"
        return text


# ------------------------------------------------------------------------------------ plans


@dataclass
class _Plan:
    """How to start one jail: the command line and what the child does before it execs."""

    argv: list[str]
    preexec: Callable[[], None] | None
    nproc_owner: int | None
    """Whose processes the process limit counts (None: the limit is already absolute)."""


def _rlimit_setter(limits: Limits, nproc: int | None) -> Callable[[], None] | None:
    """A ``preexec_fn`` setting hard limits; values are computed here, not in the child."""
    if sys.platform == "win32":
        return None
    wanted = [
        (resource.RLIMIT_AS, limits.memory_bytes),
        (resource.RLIMIT_CPU, limits.cpu_time_s),
        (resource.RLIMIT_FSIZE, limits.file_size_bytes),
        (resource.RLIMIT_CORE, 0),  # a core dump of a 1 GiB process would be written by the host
    ]
    if nproc is not None:
        wanted.append((resource.RLIMIT_NPROC, nproc))
    pairs = []
    for kind, value in wanted:
        _soft, hard = resource.getrlimit(kind)
        if hard != resource.RLIM_INFINITY:
            value = min(value, hard)
        pairs.append((kind, value))
    strict = sys.platform == "linux"

    def apply() -> None:
        for kind, value in pairs:
            try:
                resource.setrlimit(kind, (value, value))
            except (OSError, ValueError):
                if strict:  # Linux honours every one of them: failing to set one is a bug
                    raise
                # macOS refuses some limits (RLIMIT_AS below the current size): documented

    return apply


def _system_entries() -> tuple[list[tuple[str, str]], list[str]]:
    """The system as the jail sees it: symlinks to recreate, and paths to bind read-only."""
    links: list[tuple[str, str]] = []
    binds: list[str] = []
    for path in _SYSTEM_DIRS:
        if os.path.islink(path):
            links.append((os.readlink(path), path))
        elif os.path.isdir(path):
            binds.append(path)
    binds += [p for p in _SYSTEM_FILES if os.path.exists(p)]
    return links, binds


def _interpreter_paths(argv0: str) -> list[str]:
    """What the interpreter needs to start and import roboscript, read-only."""
    exe = argv0 if os.sep in argv0 else (shutil.which(argv0) or argv0)
    wanted = {sys.prefix, sys.exec_prefix, sys.base_prefix, sys.base_exec_prefix, exe}
    wanted.update(site.getsitepackages())
    wanted.add(str(_PACKAGE))
    keep = []
    for path in wanted:
        if not os.path.exists(path):
            continue
        for name in _names(path):
            # A venv inside the checkout is fine; a prefix that *contains* the checkout is not.
            if _CHECKOUT is None or not _is_within(str(_CHECKOUT), name):
                keep.append(name)
    return keep


def _names(path: str) -> list[str]:
    """The real path, and the name given when it differs and can be recreated in the jail.

    A symlinked name can be recreated only when its parent is a real folder (``/bin/python3``
    with ``/bin -> usr/bin`` cannot: ``/bin`` is itself a link in the jail).
    """
    given = os.path.abspath(path)
    real = os.path.realpath(given)
    parent = os.path.dirname(given)
    if given != real and os.path.realpath(parent) == parent:
        return [real, given]
    return [real]


def _is_within(path: str, folder: str) -> bool:
    """True when ``path`` is ``folder`` or inside it (both absolute and normalised)."""
    return path == folder or path.startswith(folder.rstrip("/") + "/")


def _visible_paths(visible: Iterable[Path]) -> list[str]:
    """Each visible path at its real location, and at the name given when that differs."""
    found = []
    for given in visible:
        names = _names(str(given))
        real = names[0]
        if not os.path.exists(real):
            raise FileNotFoundError(f"a visible path does not exist: {given}")
        if real == "/":
            raise ValueError("the whole disk cannot be visible to the student")
        if _CHECKOUT is not None and _is_within(str(_CHECKOUT), real):
            raise ValueError(f"{given} would show the whole roboscript checkout to the student")
        found += names
    return found


def _mount_points(paths: Iterable[str]) -> list[str]:
    """The bind destinations: deduplicated, none inside another (every bind is read-only)."""
    unique = sorted({p for p in paths if p not in _NEVER_BOUND}, key=lambda p: (p.count("/"), p))
    chosen: list[str] = []
    for path in unique:
        if any(_is_within(path, outer) for outer in chosen):
            continue
        if _is_within(path, "/proc") or _is_within(path, "/dev"):
            continue
        chosen.append(path)
    return sorted(chosen)


def _check_readable_by_others(paths: Iterable[str]) -> None:
    """As root the jail runs as a uid with no rights of its own: it reads what others may."""
    _check_readable_by_jail(paths, None)


_JAIL_GID_BASE = 0x7800_0000
"""A student's files are given group ``base + 4096 * grader pid + n`` in separate-user mode
(:func:`private_class`): the student's jails run in that group, and read them through it."""
_GIDS_PER_PROCESS = 4096
_JAIL_GID_END = _JAIL_GID_BASE + (1 << 28)


def _jail_group(paths: Sequence[str]) -> int | None:
    """The student's group the files were given (:func:`private_class`), if any."""
    for path in paths:
        gid = os.stat(path).st_gid
        if _JAIL_GID_BASE <= gid < _JAIL_GID_END:
            return gid
    return None


_MOST_CHECKED_ENTRIES = 20_000
"""Most files and folders of one visible folder checked for the jail's rights (discovery
refuses a submission of more than 10,000)."""


def _folder_entries(path: str) -> Iterator[str]:
    """``path``, and when it is a folder every file and folder in it (links not followed),
    at most :data:`_MOST_CHECKED_ENTRIES`."""
    yield path
    if not os.path.isdir(path):
        return
    count = 0
    for folder, folders, files in os.walk(path):
        for name in [*folders, *files]:
            count += 1
            if count > _MOST_CHECKED_ENTRIES:
                return
            yield os.path.join(folder, name)


def _check_readable_by_jail(paths: Iterable[str], group: int | None, reach: bool = False) -> None:
    """A jail run as a user of its own reads what others may, or what its student's
    ``group`` may; with ``reach`` (no bubblewrap to show it the path) it must also be able
    to pass through every folder above."""
    for path in paths:
        # a student's folder is read by the jail as a whole: each file and folder in it too
        # (a file of mode 000 in a handed-in archive is that student's setup problem, said so)
        for inside in _folder_entries(path):
            info = os.lstat(inside)
            need = 0o5 if stat.S_ISDIR(info.st_mode) else 0o4
            if stat.S_ISLNK(info.st_mode) or info.st_mode & need == need:
                continue
            if info.st_gid == group and (info.st_mode >> 3) & need == need:
                continue
            raise PermissionError(
                f"{inside} is not readable by other users (mode {info.st_mode & 0o777:o}): a"
                " jail started by root reads only what any user may; chmod -R o+rX the"
                " submissions"
            )
        folder = os.path.dirname(path)
        while reach and folder != os.path.dirname(folder):
            mode = os.stat(folder).st_mode
            if mode & 0o1 == 0 and not (os.stat(folder).st_gid == group and mode & 0o10):
                raise PermissionError(
                    f"{folder} cannot be passed through by other users (mode"
                    f" {mode & 0o777:o}): a run as a user of its own could not reach {path};"
                    " chmod o+x it"
                )
            folder = os.path.dirname(folder)


def check_visible(visible: Sequence[Path], isolation: Isolation | None = None) -> None:
    """Fail now, as a :class:`Jail` would, if these paths cannot be shown to a jail.

    The grader calls it for every submission before the first run, so a setup problem (a
    missing file, a file root's jails cannot read) is one clear error, not a class of
    failed runs.

    Raises:
        FileNotFoundError: A path does not exist.
        PermissionError: As root, a path is not readable by other users.
        ValueError: A path would show the whole disk or the roboscript checkout.
    """
    shown = _visible_paths(visible)
    isolation = isolation or detect_isolation()
    if isolation.complete and os.geteuid() == 0:
        _check_readable_by_others(shown)
    elif isolation.separate_user and os.geteuid() == 0:
        _check_readable_by_jail(shown, _jail_group(shown), reach=True)


@contextlib.contextmanager
def private_class(
    students: Sequence[Sequence[Path]],
    teacher: Sequence[Path],
    isolation: Isolation | None = None,
) -> Iterator[None]:
    """While grading in separate-user mode, make the class's files readable only where needed.

    Without bubblewrap a run sees the whole disk as a user of its own, so what it may read is
    what the file modes say. For the time of the block: each student's files and folders get
    a group of that student's (readable by the group, not by others), which that student's
    jails run in; a folder holding students' files can be passed through but not listed; the
    teacher's files (the tests) are unreadable to others; and files the grader writes
    (reports, results) are private to it (umask 077). Modes and groups are put back
    afterwards. In any other mode nothing changes.

    Args:
        students: Each student's visible files and folders.
        teacher: The tests' files.
        isolation: Defaults to :func:`detect_isolation`.
    """
    isolation = isolation or detect_isolation()
    if not (isolation.separate_user and os.geteuid() == 0):
        yield
        return
    saved: dict[str, tuple[int, int]] = {}

    def change(path: str, mode: int, group: int = -1) -> None:
        info = os.lstat(path)
        saved.setdefault(path, (stat.S_IMODE(info.st_mode), info.st_gid))
        os.chown(path, -1, group, follow_symlinks=False)
        os.chmod(path, mode)

    tops = {os.path.realpath(p) for paths in students for p in paths}
    umask = os.umask(0o077)
    try:
        for index, paths in enumerate(students):
            group = (
                _JAIL_GID_BASE
                + (os.getpid() % (1 << 16)) * _GIDS_PER_PROCESS
                + index % _GIDS_PER_PROCESS
            )
            for top in map(os.path.realpath, paths):
                for path in _tree(top):
                    mode = stat.S_IMODE(os.lstat(path).st_mode) & ~0o007
                    change(path, mode | (0o050 if os.path.isdir(path) else 0o040), group)
                folder = os.path.dirname(top)
                if folder not in tops:
                    mode = saved.get(folder, (stat.S_IMODE(os.stat(folder).st_mode), 0))[0]
                    change(folder, (mode & ~0o007) | 0o001)
        for path in map(os.path.realpath, teacher):
            change(path, stat.S_IMODE(os.stat(path).st_mode) & ~0o007)
        yield
    finally:
        os.umask(umask)
        for path, (mode, group) in reversed(saved.items()):
            with contextlib.suppress(OSError):
                os.chown(path, -1, group, follow_symlinks=False)
                os.chmod(path, mode)


def _tree(top: str) -> Iterator[str]:
    """``top`` and, for a folder, everything in it (links are neither followed nor changed)."""
    if os.path.islink(top):
        return
    yield top
    if os.path.isdir(top):
        for folder, dirs, files in os.walk(top):
            for name in [*dirs, *files]:
                path = os.path.join(folder, name)
                if not os.path.islink(path):
                    yield path


_uid_counter = 0
_uid_lock = threading.Lock()


def _jail_uid() -> int:
    global _uid_counter
    with _uid_lock:
        _uid_counter += 1
        slot = _uid_counter % _UIDS_PER_PROCESS
    return _JAIL_UID_BASE + (os.getpid() % (1 << 22)) * _UIDS_PER_PROCESS + slot


def _bubblewrap_plan(
    argv: Sequence[str],
    visible: Sequence[str],
    workdir: Path,
    env: Mapping[str, str],
    limits: Limits,
    info_fd: int | None,
    reserve: int = 0,
) -> _Plan:
    """The ``bwrap`` command line for one jail (see the module docstring for the layout)."""
    bwrap = shutil.which("bwrap")
    if bwrap is None:
        raise FileNotFoundError("bwrap is not on PATH")
    bwrap = os.path.realpath(bwrap)
    as_root = os.geteuid() == 0
    args = [bwrap, "--die-with-parent", "--new-session"]
    extra: list[str] = [bwrap]
    setpriv = ""
    if as_root:
        # bwrap run by root maps the sandbox to root outside, which escapes RLIMIT_NPROC and
        # may signal root's processes. Dropping to another uid *before* bwrap would leave it
        # unable to reach an interpreter under /root (0700). So bwrap builds the jail as root,
        # without a user namespace, and setpriv drops to the jail's own uid inside it; a second,
        # unprivileged bwrap then forbids the student any user namespace of its own.
        found = shutil.which("setpriv")
        if found is None:
            raise FileNotFoundError("setpriv is not on PATH")
        setpriv = os.path.realpath(found)
        extra.append(setpriv)
        args += ["--unshare-ipc", "--unshare-pid", "--unshare-net", "--unshare-uts"]
        args += ["--unshare-cgroup-try", "--cap-drop", "ALL"]
        for cap in ("CAP_SETUID", "CAP_SETGID", "CAP_SETPCAP"):  # setpriv's, dropped by it
            args += ["--cap-add", cap]
    else:
        # --unshare-all only *tries* a user namespace; --disable-userns needs one for sure.
        args += ["--unshare-all", "--unshare-user", "--disable-userns", "--cap-drop", "ALL"]
    if info_fd is not None:
        args += ["--info-fd", str(info_fd)]
    args += ["--proc", "/proc", "--dev", "/dev"]
    # Before the binds: a visible file under /tmp must land on top of the scratch tmpfs.
    args += ["--perms", "1777", "--size", str(limits.scratch_bytes), "--tmpfs", "/tmp"]
    links, system = _system_entries()
    for target, link in links:
        args += ["--symlink", target, link]
    mounts = _mount_points([*system, *_interpreter_paths(argv[0]), *extra, *visible])
    made: set[str] = set()
    for dest in mounts:
        # bwrap would create missing parents 0700 when run by root: make them searchable.
        parents = []
        parent = os.path.dirname(dest)
        while parent not in ("/", "/tmp") and parent not in made:
            parents.append(parent)
            parent = os.path.dirname(parent)
        for folder in reversed(parents):
            args += ["--perms", "0755", "--dir", folder]
            made.add(folder)
        args += ["--ro-bind", dest, dest]
    # bwrap leaves its own tmpfs root and /dev writable by the sandbox's owner: close them.
    args += ["--remount-ro", "/", "--remount-ro", "/dev"]
    args += ["--chdir", str(workdir), "--clearenv"]
    for key, value in env.items():
        args += ["--setenv", key, value]
    args.append("--")
    if as_root:
        uid = _jail_uid()
        args += [setpriv, f"--reuid={uid}", f"--regid={uid}", "--clear-groups"]
        args += ["--inh-caps=-all", "--bounding-set=-all", "--"]
        args += [bwrap, "--unshare-user", "--disable-userns", "--die-with-parent"]
        args += ["--cap-drop", "ALL", "--bind", "/", "/", "--dev-bind", "/dev", "/dev", "--"]
        # The uid is the jail's alone: its own processes plus the inner bwrap.
        preexec = _rlimit_setter(limits, limits.processes + 1 + reserve)
        owner = None
    else:
        preexec = None  # completed by Jail once it has counted the user's processes
        owner = os.getuid()
    args += list(argv)
    if preexec is None:
        preexec = _rlimit_setter(limits, None)
    return _Plan(args, preexec, owner)


def _tasks_of(uid: int) -> int | None:
    """How many processes and threads ``uid`` has (what RLIMIT_NPROC counts), or None."""
    if os.path.isdir("/proc/self/task"):
        return sum(
            int(fields.get(b"Threads", b"0"))
            for _pid, fields in statuses()
            if uid_of(fields) == uid
        )
    try:  # macOS and the BSDs: processes, which is what their RLIMIT_NPROC counts
        listing = subprocess.run(
            ["ps", "-A", "-o", "uid="], capture_output=True, text=True, timeout=10, check=True
        ).stdout
    except (OSError, subprocess.SubprocessError):
        return None
    return sum(1 for line in listing.split() if line == str(uid))


class _Output:
    """Standard output and error of a jailed process: pipes read without blocking, capped."""

    def __init__(self, limits: Limits) -> None:
        self._out = _Capped(limits.output_bytes)
        self._err = _Capped(limits.output_bytes)
        self._idle: tuple[int, int] | None = None
        self._closed = False
        self._streams: dict[int, _Capped] = {}
        self._open: list[int] = []

    def _attach(self, out_r: int, err_r: int) -> None:
        self._streams = {out_r: self._out, err_r: self._err}
        self._open = [out_r, err_r]
        if sys.platform != "win32":
            for fd in self._open:
                os.set_blocking(fd, False)

    def fileno_list(self) -> list[int]:
        """The descriptors of standard output and error, to wait on with select or poll.

        They stay valid (and are never reused) until :meth:`kill`; once a stream has ended its
        descriptor simply never becomes ready again.
        """
        return list(self._open) if sys.platform != "win32" else []

    def drain(self) -> None:
        """Read what the process has written so far, without blocking; keep what fits."""
        if self._closed or sys.platform == "win32":
            return
        for fd in self._open:
            self._read(fd, _READS_PER_DRAIN)

    def _read(self, fd: int, chunks: int) -> None:
        sink = self._streams.get(fd)
        if sink is None:
            return
        for _ in range(chunks):
            try:
                data = os.read(fd, _READ_CHUNK)
            except BlockingIOError:
                return
            except OSError:
                data = b""
            if not data:
                self._park(fd)
                return
            sink.feed(data)

    def _park(self, fd: int) -> None:
        """A stream ended: keep its number, but never let a poller wake up for it again.

        Closing it would leave a stale number in the caller's poller (a busy loop, or another
        file's events once the number is reused); a pipe nobody writes to is never ready.
        """
        if self._idle is None:
            self._idle = os.pipe()
        os.dup2(self._idle[0], fd, inheritable=False)
        del self._streams[fd]

    @property
    def stdout(self) -> str:
        """Standard output kept so far, with a ``… (cut: N more bytes)`` line if any was cut."""
        return self._out.text()

    @property
    def stderr(self) -> str:
        """Standard error kept so far, with a ``… (cut: N more bytes)`` line if any was cut."""
        return self._err.text()

    def _close_output(self, also: Sequence[int] = ()) -> None:
        self._closed = True
        for fd in [*self._open, *(self._idle or ()), *also]:
            with contextlib.suppress(OSError):
                os.close(fd)
        self._streams.clear()
        self._open = []
        self._idle = None


# ------------------------------------------------------------------------------------- jail


class Jail(_Output):
    """One untrusted process tree, started sandboxed.

    The process starts at once. The caller's loop waits on :meth:`fileno_list` and calls
    :meth:`drain` (a student who floods its output never blocks and never bloats the caller),
    then :meth:`poll` or :meth:`wait`, and :meth:`kill` (or leaves the ``with`` block) to end
    it. Once :meth:`poll` or :meth:`wait` returns a status, every process of the tree is gone.

    Under bubblewrap the jail also dies with the *thread* that created it (Linux's parent-death
    signal follows the creating thread): create jails from a thread that outlives them.

    Attributes:
        pid: The process the caller started (under bubblewrap, ``bwrap`` itself).
        isolation: The isolation in force.
        limits: The limits in force.
    """

    def __init__(
        self,
        argv: Sequence[str],
        *,
        visible: Sequence[Path],
        workdir: Path,
        pass_fds: Sequence[int] = (),
        limits: Limits = Limits(),
        env: Mapping[str, str] | None = None,
        isolation: Isolation | None = None,
        reserve: int = 0,
    ) -> None:
        """Start ``argv`` jailed.

        Args:
            argv: The command; ``argv[0]`` is the interpreter (usually ``sys.executable``).
            visible: Files and folders the process may read, shown read-only at their own
                absolute paths. Nothing else of the disk is visible but the system, the
                interpreter and the roboscript package, read-only. When the grader runs as
                root, each must be readable by other users (else :class:`PermissionError`).
            workdir: The process's working folder: a visible folder, or a folder holding
                visible files (it then shows only those).
            pass_fds: Descriptors the process inherits (e.g. the socket to the grader).
            limits: The resource limits.
            env: Variables added to the jail's small environment (``HOME=/tmp``, ``PATH``,
                ``LANG=C.UTF-8``, ``PYTHONDONTWRITEBYTECODE=1``); nothing else is inherited.
            isolation: Defaults to :func:`detect_isolation`.
            reserve: Processes ``argv`` itself keeps beside the student's (a fork server),
                added to the process limit.

        Raises:
            FileNotFoundError: A visible path does not exist.
            ValueError: ``workdir`` is not visible, or a visible path holds the roboscript
                checkout.
            PermissionError: As root, a visible path is not readable by other users.
        """
        super().__init__(limits)
        self.isolation = isolation or detect_isolation()
        self.limits = limits
        self._status: int | None = None
        self._tree_fd: int | None = None  # pidfd of the jail's PID 1 (bubblewrap)
        self._exit_fd: int | None = None  # pidfd of our own child
        jailed = self.isolation.complete
        shown = _visible_paths(visible)
        workdir_real = os.path.realpath(workdir)
        if not any(
            _is_within(workdir_real, path) or _is_within(path, workdir_real) for path in shown
        ):
            raise ValueError(f"the working folder {workdir} is not visible to the jail")
        if jailed and os.geteuid() == 0:
            _check_readable_by_others(shown)
        full_env = {**_BASE_ENV, **(env or {})}
        self.user: int | None = None  # the jail's own user and group (separate-user mode)
        self.group: int | None = None
        self._scratch: str | None = None
        user_kwargs: dict[str, Any] = {}
        if not jailed and sys.platform != "win32":
            # Its own writable folder, never the shared /tmp (a fork server empties it).
            self._scratch = tempfile.mkdtemp(prefix="roboscript-run-")
            full_env.update(HOME=self._scratch, TMPDIR=self._scratch)
            if self.isolation.separate_user and os.geteuid() == 0:
                self.user = _jail_uid()
                group = _jail_group(shown) or self.user
                _check_readable_by_jail(shown, group, reach=True)
                self.group = group
                os.chown(self._scratch, self.user, group)
                user_kwargs = {
                    "user": self.user,
                    "group": group,
                    "extra_groups": [],
                    "umask": 0o077,
                }
        if jailed or self.user is not None:  # no process of its user's but its own
            full_env[RUN_USER_ALONE] = "1"
        out_r, out_w = os.pipe()
        err_r, err_w = os.pipe()
        info_r = info_w = -1
        try:
            if jailed:
                info_r, info_w = os.pipe()
                plan = _bubblewrap_plan(
                    argv, shown, Path(workdir_real), full_env, limits, info_w, reserve
                )
                fds = (*pass_fds, info_w)
                child_env: dict[str, str] | None = dict(_BASE_ENV)
                cwd = "/"
            else:
                plan = _Plan(list(argv), None, os.getuid() if hasattr(os, "getuid") else None)
                fds = tuple(pass_fds)
                child_env = _host_env(full_env)
                cwd = workdir_real
            if self.user is not None:  # the user is the jail's alone: an absolute limit
                plan.nproc_owner = None
                plan.preexec = _rlimit_setter(limits, limits.processes + reserve)
            if plan.nproc_owner is not None and sys.platform != "win32":
                count = _tasks_of(plan.nproc_owner)
                # bwrap's monitor and PID 1 run as the user too, outside the student's share.
                overhead = 2 if jailed else 0
                nproc = None if count is None else count + overhead + limits.processes + reserve
                plan.preexec = _rlimit_setter(limits, nproc)
            elif plan.preexec is None:
                plan.preexec = _rlimit_setter(limits, None)
            self._proc = subprocess.Popen(
                plan.argv,
                stdin=subprocess.DEVNULL,
                stdout=out_w,
                stderr=err_w,
                pass_fds=fds,
                cwd=cwd,
                env=child_env,
                start_new_session=sys.platform != "win32",
                # Only setrlimit runs in the child (3.11's subprocess has no rlimit option).
                preexec_fn=plan.preexec,  # noqa: PLW1509
                creationflags=getattr(subprocess, "CREATE_NEW_PROCESS_GROUP", 0),
                **user_kwargs,
            )
        except BaseException:
            for fd in (out_r, err_r, info_r):
                if fd >= 0:
                    os.close(fd)
            if self._scratch is not None:
                shutil.rmtree(self._scratch, ignore_errors=True)
            raise
        finally:
            for fd in (out_w, err_w, info_w):
                if fd >= 0:
                    os.close(fd)
        self.pid = self._proc.pid
        self._attach(out_r, err_r)
        if sys.platform == "win32":
            self._start_readers()
            return
        if sys.platform == "linux":
            with contextlib.suppress(OSError):
                self._exit_fd = os.pidfd_open(self.pid)
        if info_r >= 0:
            try:
                self._tree_fd = _jail_init_fd(info_r)
            finally:
                os.close(info_r)

    def cpu_time_s(self) -> float | None:
        """CPU seconds the started process has used so far, where this process can see it
        (not under bubblewrap, whose first process is ``bwrap``: use a :class:`WarmJail`,
        whose runs name their own process)."""
        if self.isolation.complete or sys.platform != "linux" or self._status is not None:
            return None
        return process_cpu_time_s(self.pid)

    # -------------------------------------------------------------------------- lifecycle

    def poll(self) -> int | None:
        """The exit status once the process has ended, else None (never blocks for long).

        Returns:
            As :attr:`subprocess.Popen.returncode`: the exit code, or ``-N`` for a process
            ended by signal N (under bubblewrap an ``exit(128 + N)`` reads the same).
        """
        if self._status is not None:
            return self._status
        if sys.platform == "win32":
            code = self._proc.poll()
            if code is not None:
                self._status = code
            return code
        if hasattr(os, "waitid"):
            # Seen ended but not reaped: its process group stays ours to kill until we reap it.
            try:
                ended = os.waitid(os.P_PID, self.pid, os.WEXITED | os.WNOHANG | os.WNOWAIT)
            except ChildProcessError:
                ended = None
            if ended is None or ended.si_pid != self.pid:
                return None
        elif self._proc.poll() is None:  # macOS before Python 3.13 has no waitid
            return None
        self._end_tree()
        return self._status

    def wait(self, timeout_s: float) -> int | None:
        """Wait up to ``timeout_s`` seconds for the process to end, draining its output.

        Returns:
            The exit status (as :meth:`poll`), or None if it is still running.
        """
        deadline = time.monotonic() + max(0.0, timeout_s)
        while True:
            status = self.poll()
            if status is not None:
                self._finish_output()
                return status
            left = deadline - time.monotonic()
            if left <= 0:
                return None
            if sys.platform == "win32":
                time.sleep(min(left, _POLL_STEP_S))
                continue
            watch = [*self._streams, *([self._exit_fd] if self._exit_fd is not None else [])]
            step = left if self._exit_fd is not None else min(left, _POLL_STEP_S)
            _wait_readable(watch, step)
            self.drain()

    def kill(self) -> None:
        """End the whole tree now (every process the student started too) and reap it.

        Safe to call again; afterwards the output descriptors are closed and :attr:`stdout`
        and :attr:`stderr` keep what was read.
        """
        if self._closed:
            return
        if self._status is None:
            if sys.platform == "win32":
                with contextlib.suppress(OSError):
                    self._proc.kill()
                self._status = self._proc.wait()
            else:
                self._end_tree()
        self._finish_output()
        self._close()

    def _end_tree(self) -> None:
        """Kill whatever is left of the tree, then reap our child and wait out the jail."""
        # Our child is at most a zombie (unless poll() had to reap it: macOS before Python
        # 3.13), so its process group number cannot have been handed to anyone else.
        with contextlib.suppress(OSError):
            os.killpg(self.pid, signal.SIGKILL)
        if self._tree_fd is not None:
            # PID 1 of the jail's namespace: when it dies the kernel kills every process in
            # it, daemons included, and only then reports PID 1 ended.
            with contextlib.suppress(OSError):
                signal.pidfd_send_signal(self._tree_fd, signal.SIGKILL)
        code = self._proc.wait()
        if self.user is not None:  # what it started, wherever it went: the user is its own
            kill_user_processes(self.user)
        if self.isolation.complete and 128 < code <= 128 + 64:
            code = 128 - code  # bwrap reports a child killed by signal N as 128 + N
        self._status = code
        if self._tree_fd is not None:
            _wait_readable([self._tree_fd], _TEARDOWN_TIMEOUT_S)
            os.close(self._tree_fd)
            self._tree_fd = None

    def _finish_output(self) -> None:
        """Read what is left in the pipes (the writers are gone, or a daemon escaped)."""
        if self._closed or sys.platform == "win32":
            if sys.platform == "win32":
                for reader in self._readers:
                    reader.join(timeout=1.0)
            return
        for fd in list(self._streams):
            self._read(fd, 4 * _READS_PER_DRAIN)

    def _close(self) -> None:
        self._close_output([self._exit_fd] if self._exit_fd is not None else [])
        self._exit_fd = None
        if self._scratch is not None:
            shutil.rmtree(self._scratch, ignore_errors=True)
            self._scratch = None
        if self.user is not None:
            _remove_files_of(self.user)

    def _start_readers(self) -> None:
        """Windows has no non-blocking pipes for select: a thread per stream, capped alike."""

        def pump(fd: int, sink: _Capped) -> None:
            while True:
                try:
                    data = os.read(fd, _READ_CHUNK)
                except OSError:
                    break
                if not data:
                    break
                sink.feed(data)

        self._readers = [
            threading.Thread(target=pump, args=(fd, sink), daemon=True)
            for fd, sink in self._streams.items()
        ]
        for reader in self._readers:
            reader.start()

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.kill()


_SHARED_SCRATCH = ("/tmp", "/var/tmp", "/dev/shm")


def _remove_files_of(uid: int) -> None:
    """Delete what ``uid`` (a jail's own user) left in the computer's shared scratch folders."""
    for folder in _SHARED_SCRATCH:
        try:
            entries = list(os.scandir(folder))
        except OSError:
            continue
        for entry in entries:
            try:
                if entry.stat(follow_symlinks=False).st_uid != uid:
                    continue
                if entry.is_dir(follow_symlinks=False):
                    shutil.rmtree(entry.path, ignore_errors=True)
                else:
                    os.unlink(entry.path)
            except OSError:
                continue


# ------------------------------------------------------------------------------- warm jail

_SERVER_READY_TIMEOUT_S = 120.0
"""How long a fork server may take to import roboscript (a loaded machine; never a student's
time: no student code has run yet)."""
_SERVER_MODULE = "roboscript.grading.jail_server"


def warm_jails_supported() -> bool:
    """True where :class:`WarmJail` works (Linux: it needs ``fork`` and kernel-checked pids)."""
    return sys.platform == "linux"


class WarmJail:
    """One jail, started once, whose pre-imported interpreter forks a process per run.

    The runs of one student's mission see the same files under the same limits, so they can
    share one jail: the interpreter starts and imports roboscript once
    (:mod:`roboscript.grading.jail_server`), and each :meth:`start` costs a ``fork``. Between
    two runs every process the first left is killed and its scratch files are deleted, so a
    run never meets another's leftovers. Isolation is that of :class:`Jail`, per jail; hidden
    and visible runs must not share one (a run could keep what it saw for the next).

    Linux only (:func:`warm_jails_supported`); create it, like a :class:`Jail`, from a thread
    that outlives it.

    Attributes:
        exchange: A folder the jail reads, for files given to one run (:meth:`share`).
        isolation: The isolation in force.
    """

    def __init__(
        self,
        module: str,
        warm_args: Sequence[str] = (),
        *,
        visible: Sequence[Path],
        workdir: Path,
        limits: Limits = Limits(),
        env: Mapping[str, str] | None = None,
        isolation: Isolation | None = None,
    ) -> None:
        """Start the jail and its server.

        Args:
            module: What each run runs: ``module.main(argv)``, after ``module.warm_up(*
                warm_args)`` once in the server (imports, so that runs start warm).
            warm_args: Passed to ``warm_up``.
            visible: As for :class:`Jail`.
            workdir: As for :class:`Jail`.
            limits: As for :class:`Jail`, per run (each run is a process of its own).
            env: As for :class:`Jail`.
            isolation: Defaults to :func:`detect_isolation`.

        Raises:
            As :class:`Jail`.
        """
        self.isolation = isolation or detect_isolation()
        self.limits = limits
        self._folder = tempfile.mkdtemp(prefix="roboscript-jail-")
        self.exchange = Path(self._folder) / "shared"
        self.exchange.mkdir()
        # Only the jail reads it: the folder above it stays the grader's own (bubblewrap
        # shows the exchange alone, at its own path).
        self.exchange.chmod(0o755)
        if self.isolation.separate_user and os.geteuid() == 0:
            os.chmod(self._folder, 0o711)  # passed through by the jail's user, never listed
        self._count = 0
        self._ready = False
        self._running: JailedRun | None = None
        ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
        ours.setsockopt(socket.SOL_SOCKET, socket.SO_PASSCRED, 1)
        self._control = ours
        try:
            self._jail = Jail(
                [
                    sys.executable,
                    "-I",
                    "-m",
                    _SERVER_MODULE,
                    str(theirs.fileno()),
                    "group" if self.isolation.name == LIMITS_ONLY else "uid",
                    module,
                    *warm_args,
                ],
                visible=[*visible, self.exchange],
                workdir=workdir,
                pass_fds=(theirs.fileno(),),
                limits=limits,
                env=env,
                isolation=self.isolation,
                reserve=1,
            )
        except BaseException:
            ours.close()
            shutil.rmtree(self._folder, ignore_errors=True)
            raise
        finally:
            theirs.close()
        self._group = self._jail.group
        if self._group is not None:  # a user of its own, no bubblewrap: only it may read
            os.chown(self.exchange, -1, self._group)
            self.exchange.chmod(0o750)

    @property
    def alive(self) -> bool:
        """False once the server has ended (a run killed it, or :meth:`close`)."""
        return self._jail.poll() is None

    @property
    def server_output(self) -> str:
        """What the server itself wrote (its start-up errors), capped."""
        self._jail.drain()
        return self._jail.stderr

    def share(self, name: str, text: str) -> Path:
        """Write ``text`` to a file of the exchange folder that the jail can read."""
        path = self.exchange / name
        path.write_text(text, encoding="utf-8")
        if self._group is not None:
            os.chown(path, -1, self._group)
            path.chmod(0o640)
        else:
            path.chmod(0o644)
        return path

    def start(self, argv: Sequence[str], *, pass_fds: Sequence[int] = (), cwd: Path) -> JailedRun:
        """Fork a run of ``module.main(argv)`` in the jail.

        Args:
            argv: The run's arguments; the i-th of ``pass_fds`` is its descriptor ``3 + i``.
            pass_fds: Descriptors the run inherits.
            cwd: The run's working folder (visible to the jail).

        Returns:
            The run, with the interface of :class:`Jail`.

        Raises:
            OSError: The server is gone or did not answer (start a new :class:`WarmJail`).
        """
        if self._running is not None and self._running.poll() is None:
            raise RuntimeError("a WarmJail runs one run at a time")
        self._wait_ready()
        out_r, out_w = os.pipe()
        err_r, err_w = os.pipe()
        try:
            request = json.dumps({"argv": list(argv), "cwd": str(cwd)}).encode()
            fds = array.array("i", [out_w, err_w, *pass_fds])
            self._control.sendmsg(
                [request], [(socket.SOL_SOCKET, socket.SCM_RIGHTS, fds.tobytes())]
            )
        except BaseException:
            for fd in (out_r, err_r):
                os.close(fd)
            raise
        finally:
            os.close(out_w)
            os.close(err_w)
        reply, pid = self._receive(_START_TIMEOUT_S)
        run = JailedRun(self, pid, out_r, err_r)
        if "status" in reply:  # it ended before it could say it started
            run._ended(int(reply["status"]))
        elif pid is None:
            run.kill()
            raise OSError("the jail's server sent no process id for its run")
        self._running = run
        return run

    def _wait_ready(self) -> None:
        if self._ready:
            return
        reply, _pid = self._receive(_SERVER_READY_TIMEOUT_S)
        if "ready" not in reply:
            raise OSError(f"the jail's server did not start: {self.server_output[-500:]}")
        self._ready = True

    def _receive(self, timeout_s: float) -> tuple[dict[str, Any], int | None]:
        """The server's next message, and the pid it carries as credentials (if any)."""
        if not _wait_readable([self._control.fileno()], timeout_s):
            raise OSError(f"the jail's server did not answer within {timeout_s:g} s")
        data, ancillary, _flags, _addr = self._control.recvmsg(
            4096, socket.CMSG_SPACE(struct.calcsize("3i"))
        )
        if not data:
            raise OSError(f"the jail's server ended: {self.server_output[-500:]}")
        pid = None
        for level, kind, payload in ancillary:
            if level == socket.SOL_SOCKET and kind == socket.SCM_CREDENTIALS:
                pid = struct.unpack("3i", payload[: struct.calcsize("3i")])[0]
        try:
            reply = json.loads(data)
        except ValueError:
            reply = None
        if not isinstance(reply, dict):
            raise OSError("the jail's server broke its protocol")
        return reply, pid

    def close(self) -> None:
        """End the server and the jail (and a run still going)."""
        if self._running is not None:
            self._running.kill()
        self._control.close()
        self._jail.kill()
        shutil.rmtree(self._folder, ignore_errors=True)

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()


class JailedRun(_Output):
    """One run forked by a :class:`WarmJail`; used as a :class:`Jail` is.

    Once :meth:`poll` or :meth:`wait` returns a status, every process of the run is gone.

    Attributes:
        pid: The run's process, as this process sees it (to measure its CPU time).
    """

    def __init__(self, server: WarmJail, pid: int | None, out_r: int, err_r: int) -> None:
        super().__init__(server.limits)
        self.isolation = server.isolation
        self.limits = server.limits
        self.pid = pid
        # Held from the moment the run says it started: a signal sent through it reaches this
        # process or nothing, never another that got its pid once the jail reaped the run.
        self._pidfd, self._kill_by_pid = _pidfd(pid)
        self._server = server
        self._status: int | None = None
        self._attach(out_r, err_r)

    def _ended(self, status: int) -> None:
        self._status = status
        self._finish_output()
        self._close_pidfd()

    def _close_pidfd(self) -> None:
        if self._pidfd is not None:
            os.close(self._pidfd)
            self._pidfd = None

    def cpu_time_s(self) -> float | None:
        """CPU seconds the run's process has used so far (None once it is gone)."""
        return process_cpu_time_s(self.pid) if self.pid is not None else None

    def poll(self) -> int | None:
        """The run's exit status once it and everything it started are gone, else None."""
        if self._status is not None:
            return self._status
        # Whether the server lives is read before its socket: a server that sends the run's
        # status and ends just after the socket was looked at is read now, not taken for a
        # server that died under its run (which would lose the run's own status).
        server_alive = self._server.alive
        if not _wait_readable([self._server._control.fileno()], 0):
            if server_alive:
                return None
            self._ended(-signal.SIGKILL)  # its server (and jail) ended under it
            return self._status
        try:
            reply, _pid = self._server._receive(0)
        except OSError:
            self._server._jail.kill()
            self._ended(-signal.SIGKILL)
            return self._status
        self._ended(int(reply.get("status", -signal.SIGKILL)))
        return self._status

    def wait(self, timeout_s: float) -> int | None:
        """Wait up to ``timeout_s`` seconds for the run to end, draining its output."""
        deadline = time.monotonic() + max(0.0, timeout_s)
        while True:
            status = self.poll()
            if status is not None:
                return status
            left = deadline - time.monotonic()
            if left <= 0:
                return None
            _wait_readable([*self._streams, self._server._control.fileno()], min(left, 1.0))
            self.drain()

    def kill(self) -> None:
        """End the run now (and what it started); the jail stays for the next run."""
        if self._closed:
            return
        if self._status is None and self._pidfd is not None:
            with contextlib.suppress(OSError):
                signal.pidfd_send_signal(self._pidfd, signal.SIGKILL)
        elif self._status is None and self.pid is not None and self._kill_by_pid:
            with contextlib.suppress(OSError):  # a system without pidfds
                os.kill(self.pid, signal.SIGKILL)
        if self.wait(_TEARDOWN_TIMEOUT_S) is None:
            self._server._jail.kill()  # the server is stuck: the whole jail goes
            self._ended(-signal.SIGKILL)
        self._close_pidfd()
        self._close_output()

    def _finish_output(self) -> None:
        for fd in list(self._streams):
            self._read(fd, 4 * _READS_PER_DRAIN)

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.kill()


def _pidfd(pid: int | None) -> tuple[int | None, bool]:
    """A descriptor that stands for process ``pid`` for as long as it is open (Linux), and
    whether the process must instead be signalled by its pid (a system without pidfds).

    ``(None, False)``: no pid, or the process has already ended and been reaped.
    """
    if pid is None:
        return None, False
    if not hasattr(os, "pidfd_open"):
        return None, True
    try:
        return os.pidfd_open(pid), False
    except ProcessLookupError:
        return None, False
    except OSError:  # a kernel without pidfd_open (before Linux 5.3)
        return None, True


def process_cpu_time_s(pid: int) -> float | None:
    """CPU seconds (user + system) process ``pid`` has used, from ``/proc``; None if gone."""
    found = read_stat(pid)
    return None if found is None else found.cpu_s


def _wait_readable(fds: Sequence[int], timeout_s: float) -> bool:
    """Wait until one of ``fds`` is readable (or ended), at most ``timeout_s`` seconds.

    poll, not select: a grader with many files open may hand out descriptors above 1023.
    """
    poller = select.poll()
    for fd in fds:
        poller.register(fd, select.POLLIN)
    return bool(poller.poll(max(0.0, timeout_s) * 1000))


def _host_env(env: Mapping[str, str]) -> dict[str, str]:
    """The fallback's environment: the jail's own, plus what Windows needs to start at all."""
    result = dict(env)
    if sys.platform == "win32":
        for key in ("SYSTEMROOT", "WINDIR"):
            if key in os.environ:
                result[key] = os.environ[key]
    return result


def _jail_init_fd(info: int) -> int | None:
    """A pidfd of the jail's PID 1, from what bwrap writes on ``--info-fd`` once it exists."""
    data = b""
    deadline = time.monotonic() + _START_TIMEOUT_S
    while time.monotonic() < deadline:
        if not _wait_readable([info], deadline - time.monotonic()):
            break
        chunk = os.read(info, 4096)
        if not chunk:
            break
        data += chunk
    try:
        pid = int(json.loads(data)["child-pid"])
    except (ValueError, KeyError, TypeError):
        return None  # bwrap failed before starting the jail: its stderr says why
    if sys.platform != "linux":
        return None
    try:
        fd = os.pidfd_open(pid)
    except OSError:
        return None
    # Between bwrap writing the pid and us opening it, the pid could in principle have been
    # reused: accept it only if it is still the init of a nested PID namespace.
    nspid = (read_status(pid) or {}).get(b"NSpid", b"").split()  # its pid in each namespace
    if len(nspid) < 2 or nspid[-1] != b"1":
        os.close(fd)
        return None
    return fd
