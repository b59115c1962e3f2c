"""The mission process of a graded run: the only place a student's mission is loaded and run.

The grader starts it sandboxed (:mod:`roboscript.grading.sandbox`) as::

    python -I -m roboscript.grading.mission_host FD MISSION ROBOT MAX_TIME_S HANG_AFTER_S [MAP]

(``MAP``: a file holding the world's regions and start pose as JSON,
:class:`roboscript.session.WorldMap`.)

It loads the mission, connects to the robot through ``lockstep://FD`` (the world lives in the
grader's process, :mod:`roboscript.grading.world_host`), runs the mission exactly as
``roboscript run`` would, and reports what only it can know: that the mission loaded, each
state it entered, each line it printed, and how it ended. The world timestamps every report
itself and trusts none of them with a name, a score or a verdict.

The mission's code is timed here exactly as ``roboscript run`` times it
(:class:`roboscript.watchdog.Watchdog`, on the code's own time, never the machine's load): code
that does not return for ``HANG_AFTER_S`` is stopped at its line, and code that takes too long
per tick too often ends the run as too slow (:class:`roboscript.watchdog.TickBudget`). The final
report says which, so the world can name it; a report can only make the student's own run
worse, and the world bounds the process's CPU time itself for a process that does not report.
No diagnostic runs on another thread: reading a running thread's frames from elsewhere is not
safe, and a stack-dumping timer once crashed healthy runs on a busy machine.

What only the mission's own code can have done is said so: a ``KeyboardInterrupt`` (no one
presses Ctrl-C in a graded run), or any signal it sends its own process (``os.kill``,
``os.killpg``, ``signal.raise_signal``, ``signal.pthread_kill``: SIGTERM and SIGHUP as much as
SIGINT or SIGUSR1), is its crash at its line, and so is a SIGTERM or SIGHUP that its process
or a program it started sends around them (``ctypes``, ``kill -TERM $PPID``): the process
learns who sent each one. A SIGTERM or SIGHUP from anywhere else (a teacher's ``kill``, a
process manager) keeps its own sentence. A wire that fails under it is a
connection it broke itself, and ``os.fork()`` is refused, as a copy of the process would drive
the same robot.

What would keep roboscript from saying where the mission's code went wrong is kept from it:
the watchdog's SIGALRM and timer cannot be changed, ignored or blocked by the mission
(:data:`WATCHDOG_ALARM`), its recursion limit stays within :data:`RECURSION_LIMITS`, and a
mission that closes its own standard output or error loses what it prints there, not its run.
"""

from __future__ import annotations

import _thread
import contextlib
import errno
import io
import itertools
import json
import logging
import operator
import os
import signal
import subprocess
import sys
import threading
import traceback
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from types import FrameType
from typing import TYPE_CHECKING, Any, NamedTuple, TextIO

from roboscript.code_owner import ROBOSCRIPT, is_student_file, owner_of_file
from roboscript.interrupts import (
    OUTSIDE_SIGNALS,
    RUN_USER_ALONE,
    Interrupted,
    exit_status_for,
    reason_for,
    signal_name,
)
from roboscript.interrupts import install as install_interrupts
from roboscript.mission.channels import MAX_PRINTED_LINES, PRINTED_LINE_CHARS
from roboscript.transport.lockstep import Kind, WorldChannel, WorldStoppedError
from roboscript.watchdog import (
    DEFAULT_LIMIT_S,
    RECURSION_LIMITS,
    RunawayCode,
    Watchdog,
    alarm_kept_sentence,
    bound_recursion,
    keep_alarm,
)

if TYPE_CHECKING:
    from roboscript.mission.cause import TransitionCause

__all__ = [
    "LOAD_LIMIT_S",
    "ONE_PROCESS",
    "RECURSION_LIMITS",
    "STATE_CLAIM_BYTES",
    "WATCHDOG_ALARM",
    "WIRE_BROKEN",
    "WIRE_LOST",
    "WIRE_LOST_EXIT",
    "main",
    "print_payload",
    "state_payload",
    "warm_up",
]

_REASON_CHARS = 500
_NAME_BYTES = 256

STATE_CLAIM_BYTES = 4096
"""Most bytes of the account that follows a state's name in a ``Q`` frame: a cause is a few
hundred; a longer one is not sent (and the world ignores one that is)."""

WIRE_LOST_EXIT = 3
"""The mission process's exit status when its wire to the world closed under it (the world
never closes it first, so the mission's own code did: a descriptor it did not open), after
writing :data:`WIRE_LOST` on its standard error (a student's own ``os._exit(3)`` does not)."""

WIRE_LOST = "roboscript: the wire to the simulated robot closed under the mission"

WIRE_BROKEN = (
    "the mission's process broke its own connection to the simulated robot: its code closed"
    " or changed a connection it did not open (a socket or file descriptor)"
)
"""Why a run whose wire failed under the mission crashed. The world never closes the wire
first, so a wire that fails (closed, replaced with ``dup2``, made non-blocking, shut down,
given a timeout) was broken by the mission's own code; said the same whether the mission could
still send its end (:func:`main`) or not (the world's ``crash_message``)."""

ONE_PROCESS = (
    "a graded mission runs in one process: os.fork() would copy it, and the copy would"
    " drive the same robot"
)
"""What ``os.fork()`` raises in a graded run (a :class:`PermissionError`): two copies of a
mission on one wire would each take the other's answers, and the world could only say the
wire broke. Programs started with ``subprocess`` are not copies, and still run."""

LOAD_LIMIT_S = 10.0
"""Own seconds loading the mission (its file, and the modules it imports) may take: far
outside what the hang limit allows a tick, since loading is not the student's code's pace."""


def main(argv: Sequence[str] | None = None) -> int:
    """Run one mission over the lockstep wire; the exit status means nothing to the grader.

    Returns:
        0, or ``128 + N`` when signal N ended the run or came while it closed (as
        ``roboscript run`` exits), 2 for a mission that did not load,
        :data:`WIRE_LOST_EXIT` when its wire to the world closed.
    """
    args = list(sys.argv[1:] if argv is None else argv)
    fd, mission_path, robot, max_time_s, hang_after_s = (
        int(args[0]),
        args[1],
        args[2],
        float(args[3]),
        float(args[4]),
    )
    world_map = args[5] if len(args) > 5 else None
    logging.disable(logging.WARNING)
    # SIGTERM and SIGHUP, as Ctrl-C, stop the robot on the way out and end the run as
    # interrupted, saying which (by default they would end the process mid-tick, the robot
    # still driving, read by the world as a crash of the student's).
    install_interrupts()
    _own_signals()
    _one_process()
    _bounded_recursion()
    _watchdog_alarm_kept()
    sys.stdout, sys.stderr = _KeptStream(sys.stdout), _KeptStream(sys.stderr)
    channel = WorldChannel.for_fd(fd)
    try:
        return _run(channel, mission_path, robot, max_time_s, world_map, hang_after_s)
    except WorldStoppedError:
        sys.stderr.write(WIRE_LOST + "\n")
        return WIRE_LOST_EXIT
    except KeyboardInterrupt as exc:
        # A signal before the session could stop a robot (while the mission loads): the run
        # ends on it, and the teacher reads the plain sentence, not a traceback through
        # roboscript's loader.
        own = _own_interrupt(exc)
        if own is not None:  # the mission's own code, between loading and its first tick
            place = f" ({own.where})" if own.where else ""
            sys.stderr.write(f"KeyboardInterrupt: the mission's code {own.did}{place}: {own.why}\n")
            return 1
        sys.stderr.write(reason_for(exc) + "\n")
        return exit_status_for(exc)


def warm_up(robot: str = "") -> None:
    """Import what a run needs, once, in a fork server whose runs are forked from it.

    That is everything a run imports before its first tick, so that each run, a ``fork`` of
    the server, starts with nothing left to import: the loaders of both kinds of mission (and
    what checks the world a mission names), the run machinery, the lockstep port and the
    robot's driver and codec.

    Args:
        robot: The robot the runs connect to (its driver and codec are imported too), or
            ``""``.
    """
    import importlib.readers  # noqa: F401 - lists the built-in worlds a mission may name

    # warmed in the fork server before any run, not when this module is imported
    import roboscript.mission
    import roboscript.mission.python_loader
    import roboscript.mission.references
    import roboscript.mission.yaml_loader
    import roboscript.session
    import roboscript.transport.urlhandler.protocol_lockstep  # noqa: F401 - the run's port

    if robot:
        # only the robot the runs connect to is warmed
        from roboscript.drivers import driver_class
        from roboscript.profiles import get_profile

        profile = get_profile(robot)
        driver_class(profile.protocol).make_codec(profile)


def _run(
    channel: WorldChannel,
    mission_path: str,
    robot: str,
    max_time_s: float,
    world_map: str | None = None,
    hang_after_s: float = DEFAULT_LIMIT_S,
) -> int:
    # the mission side loads after main() arms the stuck-watch, so a slow start is seen too
    from roboscript.errors import CapabilityError, InputError
    from roboscript.mission import mission_for_robot
    from roboscript.mission.channels import copied_prints
    from roboscript.mission.student_code import is_student_file, shown_path, stuck_at

    printed = itertools.count(1)

    def on_print(line: str) -> None:
        # never raised in the student's print(): the next tick's question ends the run
        with contextlib.suppress(WorldStoppedError):
            channel.send(Kind.PRINT, print_payload(line, next(printed)))

    try:
        # a Python mission runs when imported: a loop there is stopped at its line, and what
        # it prints is sent as it is printed (the world records it as before the start)
        with Watchdog(LOAD_LIMIT_S, stuck_at, watched=is_student_file), copied_prints(on_print):
            mission, profile, _warnings = mission_for_robot(mission_path, robot)
    except RunawayCode as exc:
        reason = exc.reason[:_REASON_CHARS]  # a frame has a size limit: the world keeps 500
        channel.send_json(Kind.LOAD_ERROR, {"message": reason, "code_stopped": "hung"})
        return 2
    except InputError as exc:
        problems = [p.format() for p in getattr(exc, "problems", None) or [exc]]
        message = problems[0][:_REASON_CHARS]
        channel.send_json(Kind.LOAD_ERROR, {"message": message, "more": len(problems) - 1})
        return 2
    except KeyboardInterrupt as exc:
        own = _own_interrupt(exc, shown_path)
        if own is None:  # SIGTERM, SIGHUP from outside: main() ends the run on its sentence
            raise
        message = f"{own.where + ': ' if own.where else ''}error: {own.did}: {own.why}"
        channel.send_json(Kind.LOAD_ERROR, {"message": message[:_REASON_CHARS]})
        return 2
    channel.send_json(Kind.LOADED, {"mission": mission.name[:_NAME_BYTES]})

    # the run machinery loads only for a mission that loaded: a broken one is answered at once
    from roboscript.session import WorldMap, run_session

    actions = {name: state.action_name for name, state in mission.states.items()}

    def on_state(_t_s: float, name: str, cause: TransitionCause) -> None:
        channel.send(Kind.STATE, state_payload(name, actions.get(name), cause))

    try:
        session = run_session(
            mission,
            profile,
            port=f"lockstep://{channel_fd(channel)}",
            max_time_s=max_time_s,
            on_state=on_state,
            world_map=None
            if world_map is None
            else WorldMap.from_json(Path(world_map).read_text(encoding="utf-8")),
            runaway_after_s=hang_after_s,
            on_print=on_print,
        )
    except CapabilityError as exc:
        message = f"it does not fit the robot: {exc}"[:_REASON_CHARS]
        channel.send_json(Kind.LOAD_ERROR, {"message": message})
        return 2
    result = session.result
    said, code_error = result.reason, result.code_error
    ended_by = session.interrupted_by if result.outcome == "error" else None
    own = None if ended_by is None else _own_interrupt(ended_by, shown_path)
    if not code_error and own is not None:  # it ended the run (a finished one keeps its end)
        said = f"your code {own.did} in state '{result.final_state}': {own.why}"
        said += f" ({own.where})" if own.where else ""
        code_error = True
    elif not code_error and result.outcome == "error" and channel.broken:
        said, code_error = WIRE_BROKEN, True
    channel.send_json(
        Kind.FINISH,
        {
            "outcome": result.outcome,
            "final_state": result.final_state,
            "reason": (said or "")[:_REASON_CHARS] or None,
            "code_error": code_error,
            "code_stopped": session.code_stopped,
        },
    )
    # a signal that ended the run, or came while the port closed after it: its own status
    return session.interrupted


_NO_CTRL_C = "no one presses Ctrl-C in a graded run; a mission ends by going to a final state"
_NO_SIGNAL = "a mission ends by going to a final state, not by sending itself a signal"


_CAUGHT_SIGNALS = tuple(
    getattr(signal, name)
    for name in ("SIGQUIT", "SIGUSR1", "SIGUSR2", "SIGVTALRM", "SIGPROF", "SIGPOLL", "SIGPWR")
    if hasattr(signal, name)
)
"""Signals that would end the process where it stands, that only the mission's own code can
have sent: they end the run as Ctrl-C does, at its line. (Not SIGALRM, the watchdog's; not
the signals of a fault, SIGSEGV and its kin, which a handler would only make repeat.)"""

_sent_itself: dict[int, str] = {}
"""The signals the mission's own code sent its own process (:func:`_own_signals`), each with
how, said after its name: ``""`` from its own process, :data:`_THROUGH_A_PROGRAM` from another
process of its run (:func:`_sender_of`)."""

_THROUGH_A_PROGRAM = " (through a program it started)"

_started_programs: set[int] = set()
"""The process ids of the programs the mission started (:func:`_spawned_unblocked`): a
signal one of them sends is the run's, even once it has ended and cannot be seen any more."""

_program_lines: dict[int, tuple[str, int]] = {}
"""Where the mission's code started each program (:data:`_started_programs`), by its pid: the
student's file and line."""

_sent_from: dict[int, tuple[str, int]] = {}
"""For a signal a program of the run sent, where the mission's code started that program:
the line its stop names, wherever the mission's code had got to when the signal was handed on
(it is handed on from another thread, so that moment is the machine's, not the code's)."""

_spawning = threading.Condition()
"""Held while a program is being started; notified once its pid is in
:data:`_started_programs`."""

_spawns_under_way = 0
"""Programs being started now: one may signal the run before its starter has learned its
pid (it runs, and may already be gone, before ``fork_exec`` returns)."""

_SPAWN_WAIT_S = 1.0
"""How long a signal of unknown sender waits for the programs being started to be noted (a
bound, for a mission that starts programs without end on many threads)."""

_received_apart: frozenset[int] = frozenset()
"""The signals received on a thread of their own (:func:`_senders_told_apart`): blocked in
every other thread, whatever the mission's code asks."""

_WAKE = signal.SIGURG
"""What wakes the main thread out of a blocking call (a ``sleep``, a wait on a process) when
the thread that receives SIGTERM and SIGHUP hands one on: a signal nothing else sends a graded
run, ignored by default, given a handler that does nothing."""

_raise_signal, _pthread_kill, _getsignal = (
    signal.raise_signal,
    signal.pthread_kill,
    signal.getsignal,
)
_interrupt_main = _thread.interrupt_main
_set_mask: Callable[[int, Iterable[int]], set[int]] | None = getattr(
    sys.modules.get("_signal"), "pthread_sigmask", None
)
"""The functions as Python gives them, before :func:`_own_signals` and
:func:`_watchdog_alarm_kept` wrap them for the mission's code (``_signal``'s ``pthread_sigmask``:
``signal``'s calls that one, which the mission's code cannot be let to unblock SIGTERM; it is
not on every system)."""


class _OwnStop(NamedTuple):
    """A stop the mission's own code caused: what it did, where (``file:line`` or ``""``),
    and why that is no way to end a graded run."""

    did: str
    where: str
    why: str


def _own_interrupt(
    exc: KeyboardInterrupt, shown: Callable[[str], str] = os.path.basename
) -> _OwnStop | None:
    """What the mission's own code did, and where, when ``exc`` is a ``KeyboardInterrupt`` it
    caused; ``None`` for a SIGTERM or SIGHUP from outside.

    A graded run's process has no terminal and a session of its own, and the grader ends it
    with SIGKILL: a bare ``raise KeyboardInterrupt``, SIGINT (``signal.raise_signal``,
    ``_thread.interrupt_main()``) or a signal of :data:`_CAUGHT_SIGNALS` can only come from
    the mission's own code; SIGTERM and SIGHUP are its own when its code sent them
    (:func:`_own_signals`) or a process of its run did (:func:`_senders_told_apart`), and keep
    their own sentence otherwise (see the teachers' guide).
    ``shown`` names the student's file as the student would (their path inside the
    submission).
    """
    signum = exc.signum if isinstance(exc, Interrupted) else None
    if signum in OUTSIDE_SIGNALS and signum not in _sent_itself:
        return None
    if signum is None:
        did, why = f"raised {type(exc).__name__}", _NO_CTRL_C
    elif signum == signal.SIGINT:
        did, why = "sent its own process SIGINT (Ctrl-C's signal)", _NO_CTRL_C
    else:
        did, why = f"sent its own process {signal_name(signum)}", _NO_SIGNAL
        did += _sent_itself.get(signum, "")
    student = [f for f in traceback.extract_tb(exc.__traceback__) if is_student_file(f.filename)]
    where = f"{shown(student[-1].filename)}:{student[-1].lineno}" if student else ""
    started_at = _sent_from.get(signum) if signum is not None else None
    if started_at is not None:  # where its code started the program that sent it
        where = f"{shown(started_at[0])}:{started_at[1]}"
    return _OwnStop(did, where, why)


def _own_signals() -> None:
    """Note every signal the mission's own code sends its own process, and end the run at its
    line on each one that would end the process where it stands.

    ``os.kill`` and ``os.killpg`` aimed at this process or its group (``0`` included),
    ``signal.raise_signal`` and ``signal.pthread_kill`` (any of its threads) note the signal
    in :data:`_sent_itself` before sending it. SIGKILL and SIGSTOP, which no handler can
    catch, are not sent from the main thread: the run ends there as on any other signal it
    sends itself, at its line, its robot stopped (not an unexplained kill, nor a pause the
    world waits out). SIGTERM and SIGHUP sent around them (``ctypes``, a program it started)
    are told from a signal from outside by who sent them (:func:`_senders_told_apart`).
    """
    handler = signal.getsignal(signal.SIGINT)  # install_interrupts(): raises Interrupted
    assert callable(handler)  # install_interrupts() has just set it
    for signum in _CAUGHT_SIGNALS:
        signal.signal(signum, handler)
    waited = _senders_told_apart()
    kill, killpg, raise_signal, pthread_kill = (
        os.kill,
        os.killpg,
        signal.raise_signal,
        signal.pthread_kill,
    )
    set_mask = _set_mask
    getpid, getpgrp = os.getpid, os.getpgrp
    uncatchable = {int(signal.SIGKILL), int(signal.SIGSTOP)}

    def note(signum: object) -> int | None:
        number = _as_int(signum)
        if number is None:
            return None
        _sent_itself.setdefault(number, "")
        if number in uncatchable and threading.current_thread() is threading.main_thread():
            handler(number, None)  # raises Interrupted here, as the signal's handler would
        return number

    def unblocked(number: int | None, send: Callable[[], None]) -> None:
        """Send with the signal unblocked in this thread, so that it lands here, at once, as
        it did before :func:`_senders_told_apart` blocked it."""
        if number not in waited or set_mask is None:
            send()
            return
        set_mask(signal.SIG_UNBLOCK, {number})
        try:
            send()
        finally:
            set_mask(signal.SIG_BLOCK, {number})

    def own_kill(pid: int, signum: int, /) -> None:
        if pid in (0, getpid(), -getpgrp()):
            number = note(signum)
            unblocked(number, lambda: kill(pid, signum))
            return
        kill(pid, signum)

    def own_killpg(pgid: int, signum: int, /) -> None:
        if pgid in (0, getpgrp()):
            number = note(signum)
            unblocked(number, lambda: killpg(pgid, signum))
            return
        killpg(pgid, signum)

    def own_raise_signal(signum: int, /) -> None:
        number = note(signum)
        unblocked(number, lambda: raise_signal(signum))

    def own_pthread_kill(thread_id: int, signum: int, /) -> None:
        number = note(signum)
        if number in waited and thread_id != threading.get_ident():
            pthread_kill(thread_id, 0)  # a thread that does not exist is still an error
            _hand_on(number)  # blocked in every thread: it would wait there forever
            return
        unblocked(number, lambda: pthread_kill(thread_id, signum))

    wrapped = {
        "kill": own_kill,
        "killpg": own_killpg,
        "raise_signal": own_raise_signal,
        "pthread_kill": own_pthread_kill,
    }
    for module in (os, sys.modules.get("posix"), signal, sys.modules.get("_signal")):
        for name, wrapper in wrapped.items():
            if module is not None and hasattr(module, name):
                setattr(module, name, wrapper)

    def own_interrupt_main(signum: int = signal.SIGINT, /) -> None:
        note(signum)  # its handler runs as the signal's would: a SIGTERM so made is its own
        _interrupt_main(signal.Signals(signum))  # what it raises for a wrong one, as Python's

    _thread.interrupt_main = own_interrupt_main


def _senders_told_apart() -> frozenset[int]:
    """Receive SIGTERM and SIGHUP on a thread of their own, which learns who sent each one.

    Python's handlers are not told the sender, so both signals are blocked in every thread
    (this one first, before any other exists: threads inherit it) and taken by a thread that
    waits for them (``sigwaitinfo``). One sent by the run itself (its own process through
    ``ctypes``, or a program it started: :func:`_sender_of`) is noted in :data:`_sent_itself`;
    then each is handed on to the main thread as it would have landed there
    (:func:`_hand_on`), so a signal from outside keeps its own sentence. Where the system
    cannot wait for a signal (not Linux), nothing changes and ``set()`` is returned.

    Returns:
        The signals now received on that thread.
    """
    set_mask = _set_mask
    user_alone = os.environ.pop(RUN_USER_ALONE, "") == "1"  # read before the mission can
    if set_mask is None or not hasattr(signal, "sigwaitinfo") or not OUTSIDE_SIGNALS:
        return frozenset()
    global _received_apart
    waited = _received_apart = frozenset(OUTSIDE_SIGNALS)
    signal.signal(_WAKE, _woken)
    for signum in waited:
        _note_if_spawned(signum)
    set_mask(signal.SIG_BLOCK, waited)
    pid = os.getpid()

    def receive() -> None:
        set_mask(signal.SIG_BLOCK, set(signal.valid_signals()))  # the others go elsewhere
        while True:
            info = signal.sigwaitinfo(waited)
            how = _sender_of(info, pid, user_alone)
            if how is not None:
                _sent_itself.setdefault(info.si_signo, how)
                started_at = _program_lines.get(info.si_pid)
                if started_at is not None:
                    _sent_from.setdefault(info.si_signo, started_at)
            _hand_on(info.si_signo)

    try:
        threading.Thread(target=receive, name="roboscript-signals", daemon=True).start()
    except RuntimeError:  # no thread to be had: the signals land as they always did
        set_mask(signal.SIG_UNBLOCK, waited)
        _received_apart = frozenset()
        return _received_apart
    _spawned_unblocked(waited)
    return waited


def _student_line(frame: FrameType | None) -> tuple[str, int] | None:
    """The innermost line of a student's file on ``frame``'s stack, or None."""
    while frame is not None:
        if is_student_file(frame.f_code.co_filename):
            return frame.f_code.co_filename, frame.f_lineno
        frame = frame.f_back
    return None


def _note_if_spawned(signum: int) -> None:
    """Have ``signum``'s handler note it as the run's own when it lands while a program is
    being started.

    The starter unblocks the signal while it starts a program, so that the program gets it
    unblocked (:func:`_spawned_unblocked`): a program that signals its starter at once (a
    ``kill`` it ran) can land it there, on the main thread, before ``fork_exec`` returns, where
    no sender is told. Nothing outside the run aims at a mission process in that moment (the
    teacher's signals go to the grader), so it is the run's.
    """
    handler = signal.getsignal(signum)
    if not callable(handler):
        return

    def noted(number: int, frame: FrameType | None) -> Any:
        if _spawns_under_way:
            _sent_itself.setdefault(number, _THROUGH_A_PROGRAM)
        return handler(number, frame)

    signal.signal(signum, noted)


def _spawned_unblocked(waited: frozenset[int]) -> None:
    """Start the programs the mission starts with ``waited`` unblocked, as they would be
    without :func:`_senders_told_apart`: a program inherits the signals its starter blocks,
    and one that cannot be ended by SIGTERM (``Popen.terminate()``) would hang the run.

    Every way a graded mission can start a program goes through one of these (``os.fork`` is
    refused): ``subprocess``'s ``fork_exec`` and ``os.posix_spawn``, and ``os.system``.
    """
    set_mask = _set_mask
    assert set_mask is not None  # _senders_told_apart() blocks them only where it exists
    system = getattr(os, "system", None)

    def unblocked(spawn: Callable[..., Any]) -> Callable[..., Any]:
        def spawn_unblocked(*args: Any, **kwargs: Any) -> Any:
            global _spawns_under_way
            with _spawning:
                _spawns_under_way += 1
            started: Any = None
            set_mask(signal.SIG_UNBLOCK, waited)  # in this thread, for the program it starts
            try:
                started = spawn(*args, **kwargs)
            finally:
                set_mask(signal.SIG_BLOCK, waited)
                with _spawning:
                    if spawn is not system and isinstance(started, int):
                        _started_programs.add(started)  # its pid: a signal it sends is the run's
                        line = _student_line(sys._getframe(1))
                        if line is not None:
                            _program_lines[started] = line
                    _spawns_under_way -= 1
                    _spawning.notify_all()
            return started

        return spawn_unblocked

    spawners = [(subprocess, "_fork_exec"), (sys.modules.get("_posixsubprocess"), "fork_exec")]
    for module in (os, sys.modules.get("posix")):
        spawners += [(module, "posix_spawn"), (module, "posix_spawnp"), (module, "system")]
    for module, name in spawners:
        spawn = getattr(module, name, None)
        if callable(spawn):
            setattr(module, name, unblocked(spawn))


def _sender_of(info: signal.struct_siginfo, pid: int, user_alone: bool) -> str | None:
    """How the run sent itself the signal ``info`` describes, said after its name (see
    :data:`_sent_itself`), or ``None`` when it came from outside the run.

    Its own process is ``pid``. A sender of ``0`` is outside its PID namespace (the grader's
    side of bubblewrap) or the kernel. Another sender is the run's when its user is the run's
    alone (``user_alone``, see :data:`~roboscript.interrupts.RUN_USER_ALONE`), when the
    mission started it (:data:`_started_programs`), or, where the run shares its user with the
    teacher, when it is still there to be seen in the run's own session (a program started by
    one it started).
    """
    if info.si_pid == pid:
        return ""
    if info.si_pid == 0:
        return None
    if info.si_pid in _started_programs or (user_alone and info.si_uid == os.getuid()):
        return _THROUGH_A_PROGRAM
    with _spawning:  # a program just started may signal before its starter has noted it
        _spawning.wait_for(lambda: _spawns_under_way == 0, timeout=_SPAWN_WAIT_S)
        if info.si_pid in _started_programs:
            return _THROUGH_A_PROGRAM
    try:
        with open(f"/proc/{info.si_pid}/stat", "rb") as stat:
            session = int(stat.read().rsplit(b")", 1)[1].split()[3])
    except (OSError, ValueError, IndexError):
        session = None
    if info.si_pid in _started_programs:  # noted, and reaped, while /proc was read
        return _THROUGH_A_PROGRAM
    return _THROUGH_A_PROGRAM if session == os.getsid(0) else None


def _hand_on(signum: int) -> None:
    """Deliver ``signum`` to the main thread as the system would have, had it not been blocked:
    its handler runs there (a blocking call woken by :data:`_WAKE`), nothing happens if it is
    ignored, and its default action ends the process."""
    handler = _getsignal(signum)
    if handler is signal.SIG_IGN:
        return
    if callable(handler):
        _interrupt_main(signal.Signals(signum))
        main = threading.main_thread().ident
        if main is not None:
            with contextlib.suppress(OSError, ValueError):
                _pthread_kill(main, _WAKE)
        return
    set_mask = _set_mask
    if set_mask is not None:  # the default action: the process ends by the signal
        set_mask(signal.SIG_UNBLOCK, {signum})
    _raise_signal(signum)


def _woken(_signum: int, _frame: FrameType | None) -> None:
    """:data:`_WAKE`'s handler: the signal it woke the main thread for runs after it."""


def _one_process() -> None:
    """Keep the mission in this one process: ``os.fork()`` raises (see :data:`ONE_PROCESS`).
    A copy made all the same (``ctypes``' fork goes around it) ends at its first word on the
    wire, before a byte (:class:`~roboscript.transport.lockstep.WorldChannel`)."""

    def refused(*_args: object, **_kwargs: object) -> int:
        raise PermissionError(errno.EPERM, ONE_PROCESS)

    for module in (os, sys.modules.get("posix")):
        for name in ("fork", "forkpty"):
            if module is not None and hasattr(module, name):
                setattr(module, name, refused)


WATCHDOG_ALARM = alarm_kept_sentence("a graded mission")
"""What a graded mission's ``signal.signal(signal.SIGALRM, ...)``, ``signal.alarm``,
``signal.setitimer(signal.ITIMER_REAL, ...)`` or ``signal.pthread_sigmask`` blocking SIGALRM
raises (a :class:`PermissionError`): with the watchdog's alarm gone, a loop that never ends
could only be stopped by the world's CPU bound, which cannot say at which line."""


def _watchdog_alarm_kept() -> None:
    """Refuse every change to the watchdog's SIGALRM and timer made by code that is not
    roboscript's own (see :data:`WATCHDOG_ALARM`); SIGTERM and SIGHUP stay with the thread
    that learns who sent them."""
    keep_alarm(
        "a graded mission",
        lambda filename: owner_of_file(filename) != ROBOSCRIPT,
        kept_blocked=_received_apart,
    )


def _as_int(value: object) -> int | None:
    """``value`` as a signal's or a timer's number, or ``None`` (the call itself then says
    what is wrong with it)."""
    try:
        return operator.index(value)  # type: ignore[arg-type]
    except TypeError:
        return None


def _bounded_recursion() -> None:
    """Keep ``sys.setrecursionlimit`` within :data:`RECURSION_LIMITS`: outside, it raises
    ``ValueError`` at the student's line, saying why."""
    bound_recursion("a graded mission's")


class _KeptStream(io.TextIOBase):
    """The mission process's standard output or error, kept writable for roboscript: a
    mission that closes its own descriptor 1 or 2 loses what is written there, but its run
    goes on and ends with its report (before, roboscript's own echo of a printed line raised
    there, outside the student's code, and the run read as an unexplained exit)."""

    def __init__(self, stream: TextIO) -> None:
        super().__init__()
        self._stream = stream

    def writable(self) -> bool:
        return True

    def write(self, text: str) -> int:
        with contextlib.suppress(OSError, ValueError):
            self._stream.write(text)
        return len(text)

    def flush(self) -> None:
        with contextlib.suppress(OSError, ValueError):
            self._stream.flush()

    def fileno(self) -> int:
        return self._stream.fileno()

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)  # buffer, errors, reconfigure...: the stream's own

    @property
    def encoding(self) -> str:  # type: ignore[override]  # read from the stream it keeps
        return self._stream.encoding


def state_payload(name: str, action: str | None, cause: TransitionCause) -> bytes:
    """A ``Q`` frame's payload: the state's name, then (after a newline) the mission's account
    of it as JSON, ``{"action", "why"}``, for the replay to show as the mission's own words.

    The account is left out when it would be longer than :data:`STATE_CLAIM_BYTES`.
    """
    head = name.replace("\n", " ").encode("utf-8", "replace")[:_NAME_BYTES]
    try:
        claim = json.dumps({"action": action, "why": cause.to_json()}, allow_nan=False)
    except ValueError:  # a condition read NaN: the name alone
        return head
    data = claim.encode("utf-8", "replace")
    return head if len(data) > STATE_CLAIM_BYTES else head + b"\n" + data


def print_payload(line: str, number: int) -> bytes:
    """A ``P`` frame's payload: the ``number``-th line the mission printed (from 1), cut to
    one character more than a record keeps (so the world can mark the cut), or nothing past
    the lines a record keeps (the world only counts those)."""
    if number > MAX_PRINTED_LINES:
        return b""
    return line[: PRINTED_LINE_CHARS + 1].encode("utf-8", "replace")


def channel_fd(channel: WorldChannel) -> int:
    """The descriptor a channel was opened on (the port URL names it)."""
    return channel.fileno()


if __name__ == "__main__":
    sys.exit(main())
