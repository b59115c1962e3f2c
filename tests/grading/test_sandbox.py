"""The sandbox students' code runs in: each test jails a small real program and checks one promise.

Every cheat a class has tried is here, run for real: reading the hidden spec or a classmate's
file, writing fake lines to the grader's output through /proc, killing the grader, editing the
installed package, a daemon outliving its run, a fork bomb, lifting the memory limit, filling
the disk, flooding the output. The tests that need bubblewrap's full isolation are skipped,
with the reason, where it is not available (macOS, Windows, a container without namespaces).
"""

from __future__ import annotations

import importlib.util
import json
import os
import re
import select
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import textwrap
import time
import uuid
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import pytest
from helpers import HANG_BOUND_S

import roboscript
from roboscript import interrupts
from roboscript.grading import processes, sandbox
from roboscript.grading.processes import live_processes
from roboscript.grading.sandbox import (
    Isolation,
    Jail,
    JailedRun,
    Limits,
    WarmJail,
    byte_compile_package,
    check_visible,
    detect_isolation,
    private_class,
    warm_jails_supported,
)

PACKAGE = Path(roboscript.__file__).resolve().parent
HERE = Path(__file__).resolve().parent

needs_bwrap = pytest.mark.skipif(
    not detect_isolation().complete,
    reason="needs bubblewrap's full isolation: " + detect_isolation().warning,
)


@pytest.fixture
def box(tmp_path: Path) -> Path:
    """The student's own folder (readable by any user, as a jail started by root needs)."""
    tmp_path.chmod(0o755)
    folder = tmp_path / "student"
    folder.mkdir(mode=0o755)
    (folder / "mission.yaml").write_text("mission: mine\n", encoding="utf-8")
    return folder


def jail(
    code: str,
    box: Path,
    *,
    limits: Limits | None = None,
    pass_fds: Sequence[int] = (),
    env: Mapping[str, str] | None = None,
) -> Jail:
    """``code`` run by this interpreter in a jail that sees ``box``."""
    argv = [sys.executable, "-I", "-c", textwrap.dedent(code)]
    return Jail(
        argv, visible=[box], workdir=box, limits=limits or Limits(), pass_fds=pass_fds, env=env
    )


def run(
    code: str, box: Path, *, limits: Limits | None = None, env: Mapping[str, str] | None = None
) -> tuple[int | None, str, str]:
    """Run ``code`` jailed to its end: its status, standard output and standard error."""
    with jail(code, box, limits=limits, env=env) as j:
        status = j.wait(HANG_BOUND_S)
        return status, j.stdout, j.stderr


def read_until(j: Jail, text: str) -> str:
    """The jail's output once ``text`` appears in it (or the jail ended, or it hung)."""
    deadline = time.monotonic() + HANG_BOUND_S
    while time.monotonic() < deadline:
        j.drain()
        if text in j.stdout or j.poll() is not None:
            break
        select.select(j.fileno_list(), [], [], 0.01)
    j.drain()
    return j.stdout


def alive_with(marker: str) -> list[int]:
    """Processes whose command line carries ``marker`` (the jail's argv and every fork)."""
    found = []
    for name in os.listdir("/proc"):
        if not name.isdigit():
            continue
        try:
            cmdline = Path(f"/proc/{name}/cmdline").read_bytes()
        except OSError:
            continue
        if marker.encode() in cmdline:
            found.append(int(name))
    return found


# The student code below must only act once it is sure to be jailed: as root, unjailed,
# os.kill(-1, 9) would end every process on the machine.
JAILED_GUARD = """
import os, sys
if os.getpid() > 64 or os.getuid() == 0:
    sys.exit("not jailed: refusing to run the hostile part")
"""


# ------------------------------------------------------------------------- both kinds of jail


def test_it_runs_and_its_status_and_output_come_back(box: Path) -> None:
    status, out, err = run(
        """
        import os, sys
        print("hello from", os.getcwd())
        print("oops", file=sys.stderr)
        sys.exit(3)
        """,
        box,
    )
    assert status == 3
    assert out == f"hello from {os.path.realpath(box)}\n"
    assert err == "oops\n"


def test_the_environment_is_the_jails_own(box: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("GRADER_SECRET", "s3cret")
    status, out, _err = run(
        "import os, json; print(json.dumps(dict(os.environ)))", box, env={"EXTRA": "1"}
    )
    assert status == 0
    env = json.loads(out)
    assert "GRADER_SECRET" not in env
    assert env["EXTRA"] == "1" and env["HOME"] == "/tmp" and env["LANG"] == "C.UTF-8"


def test_death_by_signal_reads_as_a_negative_status_like_popen(box: Path) -> None:
    status, _out, _err = run("import os, signal; os.kill(os.getpid(), signal.SIGTERM)", box)
    assert status == -signal.SIGTERM


def test_a_flood_of_output_and_a_huge_exception_are_cut(box: Path) -> None:
    limits = Limits(output_bytes=1000)
    status, out, err = run(
        """
        import sys
        sys.stdout.write("x" * 20_000_000)
        raise RuntimeError("y" * 20_000_000)
        """,
        box,
        limits=limits,
    )
    assert status == 1
    assert out == "x" * 1000 + f"\n… (cut: {20_000_000 - 1000} more bytes)\n"
    assert err.startswith("Traceback")
    assert len(err) < 1100 and "more bytes)\n" in err


def test_ended_streams_never_wake_the_callers_poller_again(box: Path) -> None:
    with jail("print('bye')", box) as j:
        fds = j.fileno_list()
        poller = select.poll()
        for fd in fds:
            poller.register(fd, select.POLLIN)
        assert j.wait(HANG_BOUND_S) == 0
        assert j.fileno_list() == fds  # the numbers stay the jail's until kill()
        assert poller.poll(0) == []  # at their end, no POLLHUP to spin on
        assert j.stdout == "bye\n"
    assert j.fileno_list() == []


def test_a_passed_descriptor_reaches_the_process(box: Path) -> None:
    ours, theirs = socket.socketpair()
    with ours, theirs:
        code = f"import os; os.write({theirs.fileno()}, b'over the wire')"
        with jail(code, box, pass_fds=[theirs.fileno()]) as j:
            assert j.wait(HANG_BOUND_S) == 0
        ours.settimeout(HANG_BOUND_S)
        assert ours.recv(100) == b"over the wire"


def test_the_working_folder_must_be_visible(box: Path, tmp_path: Path) -> None:
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    with pytest.raises(ValueError, match="not visible"):
        Jail([sys.executable, "-c", ""], visible=[box], workdir=elsewhere)
    with pytest.raises(FileNotFoundError):
        Jail([sys.executable, "-c", ""], visible=[box / "nope.yaml"], workdir=box)


@pytest.mark.skipif(
    not (PACKAGE.parent / "pyproject.toml").is_file(), reason="roboscript is not editable here"
)
def test_the_checkout_around_an_editable_install_is_never_shown(box: Path) -> None:
    with pytest.raises(ValueError, match="checkout"):
        Jail([sys.executable, "-c", ""], visible=[PACKAGE.parent], workdir=PACKAGE.parent)


def test_limits_are_positive_whole_numbers() -> None:
    with pytest.raises(ValueError, match="processes"):
        Limits(processes=0)


# --------------------------------------------------------------------------------- fallback


@pytest.fixture
def without_bwrap(monkeypatch: pytest.MonkeyPatch) -> Iterator[Isolation]:
    real_which = shutil.which
    monkeypatch.setattr(
        shutil, "which", lambda name, *a, **k: None if name == "bwrap" else real_which(name)
    )
    # As root, the fallback would first try a user of its own per run: tested below.
    monkeypatch.setattr(sandbox, "_probe_user", lambda: "not tried in this test")
    detect_isolation.cache_clear()
    yield detect_isolation()
    detect_isolation.cache_clear()


def test_without_bwrap_it_warns_in_one_line_and_limits_still_apply(
    without_bwrap: Isolation, box: Path
) -> None:
    assert not without_bwrap.complete
    assert without_bwrap.name == "resource limits only"
    assert "\n" not in without_bwrap.warning
    assert "bwrap" in without_bwrap.warning and "apt install bubblewrap" in without_bwrap.warning
    limits = Limits(memory_bytes=512 * 1024**2, cpu_time_s=30, file_size_bytes=1024**2)
    status, out, _err = run(
        """
        import resource
        for name in ("RLIMIT_AS", "RLIMIT_CPU", "RLIMIT_FSIZE", "RLIMIT_NPROC"):
            print(name, *resource.getrlimit(getattr(resource, name)))
        try:
            hog = bytearray(2 * 1024**3)
        except MemoryError:
            print("MemoryError inside")
        """,
        box,
        limits=limits,
    )
    assert status == 0
    assert "RLIMIT_CPU 30 30\n" in out
    assert f"RLIMIT_FSIZE {1024**2} {1024**2}\n" in out
    if sys.platform == "linux":  # macOS may refuse RLIMIT_AS (documented)
        assert f"RLIMIT_AS {512 * 1024**2} {512 * 1024**2}\n" in out
        assert "MemoryError inside" in out
        nproc = out.split("RLIMIT_NPROC ")[1].split()
        assert nproc[0] == nproc[1] != str(-1)  # a finite, hard limit


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="counts processes in /proc")
def test_without_bwrap_kill_ends_the_process_group(without_bwrap: Isolation, box: Path) -> None:
    marker = f"marker-{uuid.uuid4().hex}"
    code = f"""
        import os, time  # {marker}
        if os.fork() == 0:
            time.sleep(300)
        print("ready", flush=True)
        time.sleep(300)
        """
    with jail(code, box) as j:
        assert "ready" in read_until(j, "ready")
        assert len(alive_with(marker)) == 2
        j.kill()
    assert alive_with(marker) == []


# -------------------------------------------------------------------------------- bubblewrap


@needs_bwrap
def test_the_network_is_unreachable(box: Path) -> None:
    with socket.socket() as listener:
        listener.bind(("127.0.0.1", 0))
        listener.listen()
        listener.setblocking(False)
        port = listener.getsockname()[1]
        status, out, err = run(
            f"""
            import socket
            for host in ("127.0.0.1", "1.1.1.1"):
                try:
                    socket.create_connection((host, {port}), timeout=5)
                    print("connected", host)
                except OSError as exc:
                    print("unreachable", host, type(exc).__name__)
            """,
            box,
        )
        with pytest.raises(BlockingIOError):
            listener.accept()
    assert status == 0, err
    assert "connected" not in out and out.count("unreachable") == 2


@needs_bwrap
def test_files_outside_visible_cannot_be_read_or_listed(box: Path, tmp_path: Path) -> None:
    classmate = tmp_path / "classmate"
    classmate.mkdir(mode=0o755)
    (classmate / "mission.yaml").write_text("mission: theirs\n", encoding="utf-8")
    spec = tmp_path / "hidden-spec.yaml"
    spec.write_text("test: hidden\n", encoding="utf-8")
    spec.chmod(0o644)
    # The package's folder is shown; what sits beside it (an editable install's checkout:
    # missions/teacher, tests) is not. This very test file stands for the hidden specs.
    code = f"""
        import json, os
        def look(path):
            try:
                if os.path.isdir(path):
                    return sorted(os.listdir(path))
                with open(path) as handle:
                    return handle.read()
            except OSError as exc:
                return type(exc).__name__
        print(json.dumps({{
            "own": look({str(box / "mission.yaml")!r}),
            "classmate": look({str(classmate / "mission.yaml")!r}),
            "classmate_dir": look({str(classmate)!r}),
            "spec": look({str(spec)!r}),
            "test_root": look({str(tmp_path)!r}),
            "beside_package": look({str(PACKAGE.parent)!r}),
            "this_test": look({str(Path(__file__).resolve())!r}),
            "tests_dir": look({str(HERE)!r}),
            "etc": look("/etc"),
        }}))
        """
    status, out, err = run(code, box)
    assert status == 0, err
    seen = json.loads(out)
    assert seen["own"] == "mission: mine\n"
    assert seen["classmate"] == seen["spec"] == "FileNotFoundError"
    assert seen["classmate_dir"] == seen["this_test"] == seen["tests_dir"] == "FileNotFoundError"
    assert seen["test_root"] == ["student"]
    assert PACKAGE.name in seen["beside_package"]
    venv = Path(sys.prefix)
    allowed = {PACKAGE.name} | ({venv.name} if venv.parent == PACKAGE.parent else set())
    assert set(seen["beside_package"]) <= allowed
    assert set(seen["etc"]) <= {"ld.so.cache", "ld.so.conf", "ld.so.conf.d", "localtime"}


@needs_bwrap
def test_proc_shows_no_grader_process_and_its_output_is_out_of_reach(box: Path) -> None:
    me = os.getpid()
    my_cmdline = Path("/proc/self/cmdline").read_bytes().decode(errors="replace")
    code = f"""
        import os, json
        cmdlines = {{}}
        for pid in os.listdir("/proc"):
            if pid.isdigit():
                with open(f"/proc/{{pid}}/cmdline", "rb") as handle:
                    cmdlines[pid] = handle.read().decode(errors="replace")
        writes = []
        for path in ("/proc/{me}/fd/1", "/proc/{me}/fd/2"):
            try:
                with open(path, "w") as handle:
                    handle.write("FAKE-LINE passed\\n")
                writes.append(path)
            except OSError:
                pass
        print(json.dumps({{"pids": sorted(cmdlines), "cmdlines": cmdlines, "writes": writes}}))
        """
    status, out, err = run(code, box)
    assert status == 0, err
    seen = json.loads(out)
    assert all(int(pid) < 64 for pid in seen["pids"])  # a PID namespace of its own
    assert my_cmdline not in seen["cmdlines"].values()
    # Only the jail's own: bwrap (its PID 1, and as root the inner one) and the student.
    programs = {c.split("\0")[0] for c in seen["cmdlines"].values()}
    assert programs <= {
        sys.executable,
        shutil.which("bwrap"),
        os.path.realpath(shutil.which("bwrap") or ""),
    }
    assert seen["writes"] == []


@needs_bwrap
def test_signals_reach_no_one_outside(box: Path) -> None:
    canary = subprocess.Popen(
        [sys.executable, "-c", "import time; time.sleep(120)"], start_new_session=True
    )
    try:
        code = (
            JAILED_GUARD
            + f"""
import signal
for target in (os.getppid(), 1, -1, 0, {os.getpid()}, {canary.pid}):
    for sig in (signal.SIGKILL, signal.SIGTERM, signal.SIGSTOP):
        try:
            os.kill(target, sig)
        except OSError:
            pass
try:
    os.killpg(os.getpgrp(), signal.SIGKILL)
except OSError:
    pass
"""
        )
        with jail(code, box) as j:
            assert j.wait(HANG_BOUND_S) is not None
            assert "not jailed" not in j.stderr
        survived = canary.poll() is None
        state = Path(f"/proc/{canary.pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    finally:
        canary.kill()
        canary.wait()
    assert survived and state != "T"  # neither killed nor stopped


@needs_bwrap
def test_the_roboscript_package_is_read_only(box: Path) -> None:
    target = PACKAGE / "grading" / "gradebook.py"
    before = target.read_bytes()
    status, out, err = run(
        f"""
        for path, mode in (({str(target)!r}, "a"), ({str(PACKAGE / "planted.py")!r}, "w")):
            try:
                with open(path, mode) as handle:
                    handle.write("PLANTED = True\\n")
                print("wrote", path)
            except OSError as exc:
                print("refused", exc.errno)
        """,
        box,
    )
    assert status == 0, err
    # EROFS, or EACCES first where the file is not the student's
    assert out.splitlines() in (["refused 30", "refused 30"], ["refused 13", "refused 30"])
    assert target.read_bytes() == before
    assert not (PACKAGE / "planted.py").exists()


def test_a_jail_never_compiles_the_package_it_imports(box: Path) -> None:
    # A jail cannot write .pyc files: an uncompiled install would be compiled from source at
    # the start of every run, on the student's time. The grader compiles it first.
    cached = Path(importlib.util.cache_from_source(str(PACKAGE / "grading" / "mission_host.py")))
    cached.unlink(missing_ok=True)
    assert byte_compile_package.__wrapped__()
    # What a warm jail's server imports: itself, and everything a run imports.
    code = (
        "import roboscript.grading.jail_server, roboscript.grading.mission_host as m;"
        " m.warm_up('mirto')"
    )
    with Jail([sys.executable, "-I", "-v", "-c", code], visible=[box], workdir=box) as j:
        assert j.wait(HANG_BOUND_S) == 0, j.stderr
        trace = j.stderr
    package = re.escape(str(PACKAGE))
    loaded = re.findall(rf"^# \S+\.pyc matches ({package}/\S+\.py)$", trace, re.MULTILINE)
    # Nor any other module: the standard library's and the dependencies' come compiled.
    compiled = re.findall(r"^# code object from '?(\S+\.py)'?$", trace, re.MULTILINE)
    assert str(PACKAGE / "grading" / "mission_host.py") in loaded
    assert compiled == []


@needs_bwrap
def test_the_memory_limit_is_hard_and_hits_inside(box: Path) -> None:
    status, out, err = run(
        """
        import resource
        soft, hard = resource.getrlimit(resource.RLIMIT_AS)
        print("limit", soft, hard)
        for wanted in ((resource.RLIM_INFINITY, resource.RLIM_INFINITY), (hard * 4, hard * 4)):
            try:
                resource.setrlimit(resource.RLIMIT_AS, wanted)
                print("lifted")
            except (OSError, ValueError):
                print("refused")
        try:
            hog = bytearray(2 * 1024**3)
            print("allocated")
        except MemoryError:
            print("MemoryError inside")
        """,
        box,
    )
    assert status == 0, err
    limit = Limits().memory_bytes
    assert out == f"limit {limit} {limit}\nrefused\nrefused\nMemoryError inside\n"


@needs_bwrap
def test_a_fork_bomb_is_contained_and_kill_leaves_nothing(box: Path) -> None:
    marker = f"marker-{uuid.uuid4().hex}"
    code = f"""
        import os, time  # {marker}
        forked = 0
        try:
            while forked < 100_000:
                if os.fork() == 0:
                    time.sleep(300)
                    os._exit(0)
                forked += 1
        except OSError as exc:
            print("forked", forked, exc.errno, flush=True)
        time.sleep(300)
        """
    with jail(code, box, limits=Limits(processes=8)) as j:
        out = read_until(j, "forked")
        forked = int(out.split()[1])
        assert 0 < forked < 8 and out.split()[2] == "11"  # EAGAIN
        assert len(alive_with(marker)) > forked
        j.kill()
        assert alive_with(marker) == []
        assert j.poll() == -signal.SIGKILL


DAEMON = """
import os, time  # {marker}
if os.fork() == 0:
    os.setsid()
    if os.fork() == 0:
        print("daemon up", flush=True)
        time.sleep(300)
        os._exit(0)
    os._exit(0)
{then}
"""


@needs_bwrap
def test_a_double_forked_daemon_dies_when_its_run_ends(box: Path) -> None:
    marker = f"marker-{uuid.uuid4().hex}"
    with jail(DAEMON.format(marker=marker, then="os.wait()"), box) as j:
        assert j.wait(HANG_BOUND_S) == 0
        assert alive_with(marker) == []


@needs_bwrap
def test_a_double_forked_daemon_dies_with_kill(box: Path) -> None:
    marker = f"marker-{uuid.uuid4().hex}"
    with jail(DAEMON.format(marker=marker, then="time.sleep(300)"), box) as j:
        assert "daemon up" in read_until(j, "daemon up")
        assert len(alive_with(marker)) >= 4  # bwrap, its PID 1, the main process, the daemon
        j.kill()
    assert alive_with(marker) == []


@needs_bwrap
def test_the_disk_cannot_be_filled(box: Path) -> None:
    status, out, err = run(
        f"""
        import errno
        def fill(path, megabytes):
            written = 0
            try:
                with open(path, "wb") as handle:
                    for _ in range(megabytes):
                        handle.write(b"z" * 1024 * 1024)
                        handle.flush()
                        written += 1
            except OSError as exc:
                return f"{{errno.errorcode[exc.errno]}} after {{written}} MiB"
            return f"wrote {{written}} MiB"
        print("one big file:", fill("/tmp/big", 17))
        import os; os.remove("/tmp/big")
        print("scratch:", [fill(f"/tmp/part{{i}}", 10) for i in range(20)][-1])
        print("own folder:", fill({str(box / "out.bin")!r}, 1))
        print("root:", fill("/out.bin", 1))
        """,
        box,
    )
    assert status == 0, err
    lines = out.splitlines()
    assert lines[0] == "one big file: EFBIG after 16 MiB"
    assert lines[1].startswith("scratch: ENOSPC")
    assert lines[2] == "own folder: EROFS after 0 MiB"
    assert lines[3] == "root: EROFS after 0 MiB"
    assert not (box / "out.bin").exists()


@needs_bwrap
def test_nested_namespaces_are_refused(box: Path) -> None:
    status, out, err = run(
        """
        import ctypes
        libc = ctypes.CDLL(None, use_errno=True)
        CLONE_NEWUSER = 0x10000000
        print("unshare", libc.unshare(CLONE_NEWUSER), ctypes.get_errno() != 0)
        """,
        box,
    )
    assert status == 0, err
    assert out == "unshare -1 True\n"


@needs_bwrap
@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0, reason="needs root")
def test_as_root_the_student_is_not_root_and_unreadable_files_are_refused(box: Path) -> None:
    status, out, _err = run("import os; print(os.getuid(), os.getgid(), os.getgroups())", box)
    uid, gid, groups = out.split(maxsplit=2)
    assert status == 0 and uid == gid != "0" and groups.strip() == "[]"
    secret = box / "secret.yaml"
    secret.write_text("x", encoding="utf-8")
    secret.chmod(0o600)
    with pytest.raises(PermissionError, match="chmod -R o\\+rX"):
        Jail([sys.executable, "-c", ""], visible=[secret], workdir=box)


@needs_bwrap
@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0, reason="needs root")
def test_as_root_a_file_no_other_user_may_read_inside_a_students_folder_is_refused(
    tmp_path: Path,
) -> None:
    # the folder may be read, the helper in it (mode 000, kept from a handed-in archive) not:
    # the student's setup problem, said before any run, not a run that fails to read it
    tmp_path.chmod(0o755)
    student = tmp_path / "student"
    (student / "behaviours").mkdir(parents=True)
    (student / "forward.yaml").write_text("x", encoding="utf-8")
    (student / "behaviours" / "helper.py").write_text("X = 1\n", encoding="utf-8")
    (student / "behaviours" / "helper.py").chmod(0)
    with pytest.raises(PermissionError, match=r"helper\.py is not readable by other users"):
        check_visible([student])
    (student / "behaviours" / "helper.py").chmod(0o644)
    check_visible([student])


# The grader run by an ordinary user: bwrap's own user namespace, and the process limit
# counted over all of that user's processes. Run here as "nobody" with an interpreter it may
# execute; the module is loaded from its file (the package need not be importable by it).
UNPRIVILEGED_GRADER = """
import importlib.util, json, os, sys, time


def load(name, path):  # by its file: this interpreter has no roboscript installed
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


load("roboscript.grading.processes", {processes!r})
load("roboscript.interrupts", {interrupts!r})
sandbox = load("sandbox", {module!r})
iso = sandbox.detect_isolation()
code = '''
import ctypes, os, socket, time  # {marker}
libc = ctypes.CDLL(None, use_errno=True)
pids = [p for p in os.listdir("/proc") if p.isdigit()]
facts = [os.getuid(), libc.unshare(0x10000000), len(pids)]
try:
    socket.create_connection(("127.0.0.1", {port}), timeout=5)
    facts.append("connected")
except OSError:
    facts.append("unreachable")
forked = 0
try:
    while forked < 10000:
        if os.fork() == 0:
            time.sleep(300)
            os._exit(0)
        forked += 1
except OSError:
    pass
print(*facts, forked, flush=True)
time.sleep(300)
'''
folder = {folder!r}
jail = sandbox.Jail([sys.executable, "-I", "-c", code], visible=[folder], workdir=folder,
                    limits=sandbox.Limits(processes=6))
for _ in range(3000):
    jail.drain()
    if jail.stdout or jail.poll() is not None:
        break
    time.sleep(0.01)
jail.kill()
print(json.dumps({{"isolation": iso.complete, "uid": os.getuid(), "out": jail.stdout,
                  "err": jail.stderr[-2000:]}}))
"""


def _interpreter_for_nobody() -> str | None:
    for candidate in (sys.executable, "/usr/bin/python3"):
        if not os.path.exists(candidate):
            continue
        try:
            done = subprocess.run(
                [candidate, "-I", "-c", "import sys; sys.exit(0)"],
                user=65534,
                group=65534,
                extra_groups=[],
                cwd="/",
                capture_output=True,
                check=False,
            )
        except OSError:  # it may not even reach the file (/root is 0700)
            continue
        if done.returncode == 0:
            return candidate
    return None


@needs_bwrap
@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0, reason="needs root")
def test_a_grader_run_by_an_ordinary_user_gets_the_same_isolation() -> None:
    python = _interpreter_for_nobody()
    if python is None:
        pytest.skip("no interpreter the user 'nobody' may run")
    marker = f"marker-{uuid.uuid4().hex}"
    folder = tempfile.mkdtemp(prefix="roboscript-sandbox-")
    os.chmod(folder, 0o755)
    try:
        with socket.socket() as listener:
            listener.bind(("127.0.0.1", 0))
            listener.listen()
            script = UNPRIVILEGED_GRADER.format(
                module=sandbox.__file__,
                processes=processes.__file__,
                interrupts=interrupts.__file__,
                marker=marker,
                folder=folder,
                port=listener.getsockname()[1],
            )
            done = subprocess.run(
                [python, "-I", "-c", script],
                user=65534,
                group=65534,
                extra_groups=[],
                cwd="/",
                capture_output=True,
                text=True,
                timeout=HANG_BOUND_S,
                check=False,
            )
    finally:
        shutil.rmtree(folder)
    assert done.returncode == 0, done.stderr[-3000:]
    report = json.loads(done.stdout)
    assert report["isolation"] is True and report["uid"] == 65534
    uid, unshare, pids, network, forked = report["out"].split()
    assert uid == "65534" and unshare == "-1" and network == "unreachable", report
    assert int(pids) <= 3  # bwrap's PID 1 and the student's process: nothing of the grader's
    assert 0 < int(forked) < 6
    assert alive_with(marker) == []


# ----------------------------------------------------------------------- warm jails (fork server)

needs_warm = pytest.mark.skipif(not warm_jails_supported(), reason="warm jails are Linux only")

WARM_SPEC = """\
test: still
world: empty
runs:
  - {seed: 1}
  - {seed: 2}
  - {seed: 3}
max_time: 5 s
expect:
  - outcome: success
"""

# Loaded once per run: what this run finds of the run before it, then leftovers of its own.
LEFTOVERS = """\
import os, subprocess, sys, time
from roboscript import Mission, Wait, state

me = os.getpid()
alive = []
for name in filter(str.isdigit, os.listdir("/proc")):
    try:
        with open(f"/proc/{{name}}/stat") as handle:
            fields = handle.read().rsplit(")", 1)[1].split()
    except (OSError, IndexError):
        continue
    mine = os.stat(f"/proc/{{name}}").st_uid == os.getuid()
    if int(name) != me and fields[0] not in "ZX" and mine:
        alive.append(int(name))
print("FOUND", sorted(os.listdir({scratch!r})), len(alive), os.getppid(), flush=True)
with open(os.path.join({scratch!r}, "left-behind"), "w") as handle:
    handle.write("x")
# a daemon in a session of its own (a graded mission's os.fork() is refused: subprocess)
subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"], start_new_session=True)
{extra}

class Idle(Mission):
    go = state(Wait(duration_s=0.2), initial=True, on_done="end")
    end = state(final="success")
"""


def _warm_runs(box: Path, extra: str = "", scratch: str = "/tmp") -> list[Any]:
    """The three runs of WARM_SPEC in one warm jail, with LEFTOVERS as the mission."""
    from roboscript.grading.run import grade_run
    from roboscript.grading.spec import load_test_spec
    from roboscript.grading.world_host import warm_jail

    spec_file = box.parent / "still.yaml"
    spec_file.write_text(WARM_SPEC, encoding="utf-8")
    mission = box / "still.py"
    mission.write_text(LEFTOVERS.format(scratch=scratch, extra=extra), encoding="utf-8")
    spec = load_test_spec(spec_file)
    results = []
    with warm_jail(spec, str(mission)) as server:
        for variant in spec.variants:
            results.append(grade_run(spec, str(mission), variant, server=server))
    return results


def _found(result: Any) -> list[str]:
    line = next(x for x in result.debug.splitlines() if x.startswith("FOUND"))
    return line.split(" ", 1)[1].rsplit(" ", 2)


@needs_warm
@needs_bwrap
def test_a_warm_jails_runs_never_meet_each_others_leftovers(box: Path) -> None:
    first, second, third = _warm_runs(box)
    assert [r.status for r in (first, second, third)] == ["passed"] * 3, first.debug
    files, alive, server = _found(first)
    # The first run left a file and a daemon: neither is there for the next two.
    assert _found(second) == _found(third) == [files, alive, server]
    assert "left-behind" not in files


@needs_warm
@needs_bwrap
def test_a_run_that_kills_its_warm_jail_ends_alone_and_the_next_gets_a_new_jail(
    box: Path,
) -> None:
    kill_server = "import signal\nos.kill(os.getppid(), signal.SIGKILL)\ntime.sleep(1)\n"
    from roboscript.grading.run import grade_run
    from roboscript.grading.spec import load_test_spec
    from roboscript.grading.world_host import warm_jail

    spec_file = box.parent / "still.yaml"
    spec_file.write_text(WARM_SPEC, encoding="utf-8")
    mission = box / "still.py"
    mission.write_text(LEFTOVERS.format(scratch="/tmp", extra=kill_server), encoding="utf-8")
    spec = load_test_spec(spec_file)
    with warm_jail(spec, str(mission)) as server:
        result = grade_run(spec, str(mission), spec.variants[0], server=server)
        assert result.status == "crashed"
        assert not server.alive


@needs_warm
def test_a_warm_run_names_its_own_process_so_its_cpu_time_can_be_read(box: Path) -> None:
    from roboscript.grading.spec import load_test_spec
    from roboscript.grading.world_host import warm_jail

    spec_file = box.parent / "still.yaml"
    spec_file.write_text(WARM_SPEC, encoding="utf-8")
    mission = box / "still.py"
    # Loading it burns 0.3 s of CPU: the grader must see that much on the run's own process.
    spin = "t = time.process_time()\nwhile time.process_time() - t < 0.3:\n    pass\n"
    mission.write_text(LEFTOVERS.format(scratch="/tmp", extra=spin), encoding="utf-8")
    spec = load_test_spec(spec_file)
    ours, theirs = socket.socketpair()
    with warm_jail(spec, str(mission)) as server:
        args = ["3", str(mission), "mirto", "5.0", "2.0"]
        with server.start(args, pass_fds=(theirs.fileno(),), cwd=box) as run_:
            theirs.close()
            ours.settimeout(HANG_BOUND_S)
            assert ours.recv(1)  # it loaded its mission and speaks: the spin is done
            assert run_.pid is not None and run_.pid != os.getpid()
            cmdline = Path(f"/proc/{run_.pid}/cmdline").read_bytes()
            assert b"roboscript.grading.jail_server" in cmdline
            cpu_s = run_.cpu_time_s()
            assert cpu_s is not None and cpu_s >= 0.25
            run_.kill()
            assert run_.poll() is not None
            assert run_.cpu_time_s() is None  # gone, with everything it started
    ours.close()


@needs_warm
def test_a_runs_status_sent_as_its_server_ends_is_read_not_taken_for_a_kill() -> None:
    # The jail's server sends the run's status and ends between the grader's two looks (is a
    # message waiting? is the server alive?): the run keeps its own status, not a kill's.
    ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)

    class EndsAsItIsLookedAt:
        """The server's jail: it sends the run's status and ends as its life is read."""

        def poll(self) -> int | None:
            if theirs.fileno() >= 0:
                theirs.send(json.dumps({"status": 3}).encode())
                theirs.close()
            return 0

    server = object.__new__(WarmJail)
    server.limits, server.isolation = Limits(), detect_isolation()
    server._control, server._jail = ours, EndsAsItIsLookedAt()
    out_r, out_w = os.pipe()
    err_r, err_w = os.pipe()
    os.close(out_w)
    os.close(err_w)
    run_ = JailedRun(server, None, out_r, err_r)
    try:
        assert run_.poll() == 3
    finally:
        run_._close_output()
        ours.close()


def _run_of(pid: int, status_sent: int | None) -> tuple[JailedRun, socket.socket]:
    """A run of a live stand-in server (its jail never ends) whose process is ``pid``; the
    server has already sent ``status_sent`` (if not None), unread."""
    ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)

    class Lives:
        def poll(self) -> int | None:
            return None

    server = object.__new__(WarmJail)
    server.limits, server.isolation = Limits(), detect_isolation()
    server._control, server._jail = ours, Lives()
    out_r, out_w = os.pipe()
    err_r, err_w = os.pipe()
    os.close(out_w)
    os.close(err_w)
    if status_sent is not None:
        theirs.send(json.dumps({"status": status_sent}).encode())
    return JailedRun(server, pid, out_r, err_r), theirs


needs_pidfd = pytest.mark.skipif(not hasattr(os, "pidfd_open"), reason="needs pidfds (Linux)")


@needs_pidfd
def test_killing_a_run_ends_its_process() -> None:
    child = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(600)"])
    run_, theirs = _run_of(child.pid, status_sent=-signal.SIGKILL)
    try:
        run_.kill()
        assert child.wait(timeout=HANG_BOUND_S) == -signal.SIGKILL
    finally:
        child.kill()
        child.wait()
        theirs.close()
        run_._server._control.close()


@needs_pidfd
def test_killing_a_run_whose_process_was_reaped_never_signals_another_with_its_pid(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # The run ended and its jail reaped it before its status reached the grader: its pid is
    # free, and any process may get it meanwhile. The kill must reach that run or nothing.
    child = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(600)"])
    run_, theirs = _run_of(child.pid, status_sent=-signal.SIGKILL)
    child.kill()
    child.wait()  # reaped: the pid may now be anyone's
    signalled: list[int] = []
    monkeypatch.setattr(os, "kill", lambda pid, _signal: signalled.append(pid))
    try:
        run_.kill()
        assert signalled == [], "no signal by a pid that may be another process's now"
        assert run_.poll() == -signal.SIGKILL
    finally:
        theirs.close()
        run_._server._control.close()


# ------------------------------------------------------------- a user of its own (no bubblewrap)


def _separate_user() -> Isolation | None:
    """The separate-user isolation, where this computer can give it (root, an interpreter
    other users may run), else None."""
    if sys.platform != "linux" or os.geteuid() != 0 or sandbox._probe_user():
        return None
    return Isolation(sandbox.SEPARATE_USER, False, "no bubblewrap in this test")


needs_separate_user = pytest.mark.skipif(
    _separate_user() is None,
    reason="needs root and an interpreter other users may run (a user of its own per run)",
)


@pytest.fixture
def reachable(tmp_path: Path) -> Iterator[Path]:
    """A folder every user may pass through to (pytest's own are private to their user, and
    a run as a user of its own sees the real disk)."""
    folder = Path(tempfile.mkdtemp(prefix="roboscript-user-test-"))
    folder.chmod(0o711)
    yield folder
    shutil.rmtree(folder, ignore_errors=True)


@needs_separate_user
def test_as_a_user_of_its_own_a_run_reads_only_its_students_files(reachable: Path) -> None:
    tmp_path = reachable
    tests = tmp_path / "tests"
    tests.mkdir()
    spec = tests / "hidden.yaml"
    spec.write_text("secret", encoding="utf-8")
    classroom = tmp_path / "class"
    ada, ben = classroom / "ada", classroom / "ben"
    for folder in (ada, ben):
        folder.mkdir(parents=True)
        (folder / "mission.yaml").write_text(folder.name, encoding="utf-8")
    before = {p: p.stat().st_mode for p in (spec, classroom, ada, ada / "mission.yaml")}
    isolation = _separate_user()
    code = textwrap.dedent(
        f"""
        import os, resource
        def read(path):
            try:
                with open(path) as handle:
                    return handle.read()
            except OSError as exc:
                return type(exc).__name__
        def listing(path):
            try:
                return len(os.listdir(path))
            except OSError as exc:
                return type(exc).__name__
        print(os.getuid() != 0, resource.getrlimit(resource.RLIMIT_NPROC))
        print(read({str(ada / "mission.yaml")!r}), read({str(ben / "mission.yaml")!r}))
        print(read({str(spec)!r}), listing({str(classroom)!r}), listing({str(ben)!r}))
        """
    )
    with private_class([[ada], [ben]], [spec], isolation):
        with Jail(
            [sys.executable, "-I", "-c", code],
            visible=[ada],
            workdir=ada,
            limits=Limits(processes=5),
            isolation=isolation,
        ) as j:
            assert j.wait(HANG_BOUND_S) == 0, j.stderr
            out = j.stdout.splitlines()
        written = tmp_path / "grades.csv"
        written.write_text("x", encoding="utf-8")
    assert out[0] == "True (5, 5)"
    assert out[1] == "ada PermissionError"
    assert out[2] == "PermissionError PermissionError PermissionError"
    # Afterwards every mode is as it was, and what the grader wrote meanwhile is its own.
    assert {p: p.stat().st_mode for p in before} == before
    assert written.stat().st_mode & 0o077 == 0


@needs_separate_user
def test_as_a_user_of_its_own_a_daemon_and_its_tmp_files_die_with_its_jail(reachable: Path) -> None:
    box = reachable / "student"
    box.mkdir()
    box.chmod(0o755)
    isolation = _separate_user()
    code = textwrap.dedent(
        """
        import os, time
        with open("/tmp/left-by-" + str(os.getuid()), "w") as handle:
            handle.write("the computer's /tmp is shared without bubblewrap")
        if os.fork() == 0:
            os.setsid()
            if os.fork() == 0:
                print("daemon up as", os.getuid(), flush=True)
                time.sleep(300)
            os._exit(0)
        time.sleep(300)
        """
    )
    with Jail(
        [sys.executable, "-I", "-c", code], visible=[box], workdir=box, isolation=isolation
    ) as j:
        uid = int(read_until(j, "\n").split()[-1])
        assert j.user == uid and live_processes(uid)
    assert live_processes(uid) == []
    assert not Path(f"/tmp/left-by-{uid}").exists()  # nor does what it left in /tmp
