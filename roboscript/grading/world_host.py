"""The world side of a graded run: the simulated robot, and everything a grade is computed from.

:func:`run_world` builds the simulation (world, body, simulated device) in the calling process,
which never loads a student's file, and starts the student's mission in a separate, sandboxed
process (:mod:`roboscript.grading.mission_host`, :mod:`roboscript.grading.sandbox`). The two
share one socket: the lockstep wire (:mod:`roboscript.transport.lockstep`), carrying the robot's
protocol bytes and the mission's scheduler time, exactly what a real robot would see.

Pose, path, tones, collisions and every time come from this side. The mission process can
report only that it loaded, which states it entered (timed here, on arrival) and how it ended;
each report is checked (known outcome, printable and short names, the final state is the last
state entered) and labelled as the mission's own in the record. With each state it may say
which action it runs and why it entered it: the replay shows that account as the mission's
words, checked and cut to size (``TransitionCause.from_claim``), and nothing is judged on it.
So are the lines it prints, timed here on arrival (the tick they were printed in), made
printable and cut to size, and only in the replay (the teacher's, and a visible run's).
A mission process that breaks the wire's rules, moves the robot before its mission starts, or
asks for more time than the test allows has its run ended here.

A run ends, in the order they can happen:

* ``invalid``: the mission did not load (its first problem is quoted);
* ``crashed``: the process ended before the mission finished, or its own code raised (the
  exception and the student's file and line are quoted from its standard error);
* ``hung``: the mission's code did not return: the mission process stopped it after
  ``hang_after_s`` of its own time at the line it was stuck on, or the process used that much
  CPU time, and more, without simulated time advancing;
* ``too slow``: its code took longer than a tick in too many ticks
  (:class:`roboscript.watchdog.TickBudget`, named at its line), or the process used far more CPU
  time than the simulated time it advanced;
* ``timeout``: a last resort: the run passed the test's wall-clock limit (counting only time
  when neither side waited for a CPU);
* otherwise the run is judged on the record: ``passed`` or ``failed``.

Every rule counts what the student's process consumed, never wall time, so a busy machine gives
the same verdicts as an idle one: the mission process times its own code's ticks exactly as
``roboscript run`` does, and this side reads the process tree's CPU time
(:mod:`roboscript.grading.cpu_time`). Starting the interpreter, imports and the robot's
handshake are outside the hang allowance (loading has an allowance of its own).

The world never blocks on the student: the socket is non-blocking, answers wait in a bounded
backlog, and a mission that floods the wire, stops reading its answers or lets the board's
output pile up past what a serial line holds is ended at once, as its own fault, in one
sentence.
"""

from __future__ import annotations

import math
import re
import select
import socket
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

from roboscript.code_owner import is_student_file
from roboscript.grading.cpu_time import (
    process_tree_cpu_s,
    process_tree_memory_bytes,
    process_tree_stopped,
    process_tree_waited_s,
)
from roboscript.grading.judge import ended_in_time, simulation_record
from roboscript.grading.latency import ask_short_slice
from roboscript.grading.mission_host import (
    LOAD_LIMIT_S,
    STATE_CLAIM_BYTES,
    WIRE_BROKEN,
    WIRE_LOST,
    WIRE_LOST_EXIT,
)
from roboscript.grading.record import MAX_GRADED_STATES, RunRecord, RunStatus
from roboscript.grading.sandbox import Jail, JailedRun, Limits, WarmJail
from roboscript.grading.spec import TestSpec, Variant
from roboscript.grading.submissions import named_files
from roboscript.interrupts import OUTSIDE_SIGNALS, Interrupted, signal_name
from roboscript.mission.cause import TransitionCause
from roboscript.mission.channels import PRINTED_LINE_CHARS, printed_line
from roboscript.mission.runner import MISSION_OUTCOMES
from roboscript.profiles import get_profile
from roboscript.replay.world_tap import WorldReplay
from roboscript.session import WorldMap
from roboscript.sim.simulation import Simulation
from roboscript.sim.world import Pose
from roboscript.transport.lockstep import (
    MAX_PAYLOAD_BYTES,
    FrameDecoder,
    FrameError,
    Kind,
    decode_json,
    decode_time,
    encode_frame,
)
from roboscript.watchdog import TICK_BUDGET, CodeClock

__all__ = [
    "DEFAULT_HANG_AFTER_S",
    "MISSION_OUTCOMES",
    "WorldRun",
    "run_world",
    "warm_jail",
]

DEFAULT_HANG_AFTER_S = 2.0
"""Seconds of its own time one tick's code may run before the run is ``hung``. An honest tick
takes well under a millisecond; only code stuck in a loop (or asleep) comes near it."""

_LOAD_CPU_S = LOAD_LIMIT_S + 10.0
"""CPU seconds starting the interpreter and loading the mission may use (the mission process
stops a mission file stuck while loading after :data:`LOAD_LIMIT_S` of its own time)."""

_CHECK_EVERY_S = 0.25
"""How often the process's CPU time is read while simulated time stands still (a sampling
step, not a limit: every verdict is on CPU time)."""

_PAUSED_FOR_S = 1.0
"""Wall seconds a process of the mission's tree may stay stopped (``SIGSTOP``) while simulated
time stands still before the run is ``hung``: a stopped process uses no CPU, so the CPU rules
never end it, and it waits for no CPU, so the wall limit would wait it out, longer the busier
the machine. A busy machine never stops a process, so this is no verdict on load."""

_SLOW_CHECK_EVERY_S = 2.0
"""How often the CPU time is compared with the simulated time advanced."""

_MAX_BACKLOG_BYTES = 2 * MAX_PAYLOAD_BYTES
"""Answers the mission has not read yet: an honest mission reads each answer before it asks
again, so the backlog is one frame at most."""

_MAX_BOARD_QUEUE_BYTES = MAX_PAYLOAD_BYTES // 2
"""Bytes the simulated board may hold for the host between two answers."""

_QUESTIONS = frozenset((Kind.TICK, Kind.SYNC, Kind.OPEN))
"""Frames the mission sends and then waits for the answer to, one at a time."""

_MAX_QUESTIONS_AT_ONCE = 16
"""Questions one read from the mission may hold (an honest mission's reads hold one)."""

_NOT_READING = "it stopped reading the robot's answers"

_NAME_CHARS = 100
_REASON_CHARS = 500
_MAX_HOST_BYTES = 32 * 1024**2
_START_SLACK_MM = 5.0
_TIME_SLACK_S = 1.0
_EXIT_GRACE_S = 1.0
_READ_CHUNK = 1 << 16
_HANDSHAKE_SLACK_S = 2.0
_MAX_CANDIDATES = 2000


@dataclass
class WorldRun:
    """What the world saw of one run (the grader judges it; see the module docstring).

    Attributes:
        status: ``""`` when the run ended and can be judged, else ``invalid``, ``crashed``,
            ``hung``, ``too slow`` or ``timeout``.
        message: One sentence for the student when ``status`` is set.
        debug: Detail for the teacher (the mission process's standard error, capped).
        loaded: True once the mission process reported its mission loaded; a run that ends
            before that ends the same way on every variant.
        record: What happened, when the run can be judged.
        ended_normally: True when the mission reached a final state by itself within the
            test's simulated time and its own code did not raise.
        replay: The run recorded from this world's simulation for the report's viewer
            (``{"header", "frames", "result"}``, see :mod:`roboscript.replay.world_tap`).
    """

    status: RunStatus | Literal[""] = ""
    message: str = ""
    debug: str = ""
    loaded: bool = False
    record: RunRecord | None = None
    ended_normally: bool = False
    replay: dict[str, Any] | None = None


@dataclass
class _Claims:
    """What the mission process reported, as received (validated on arrival)."""

    mission: str = ""
    started_s: float | None = None
    states: list[tuple[float, str]] = field(default_factory=list)
    dropped_states: int = 0
    finish: dict[str, Any] | None = None


class _ViolationError(Exception):
    """The mission process broke the wire's rules: the run ends as crashed."""


def run_world(
    spec: TestSpec,
    mission_path: str,
    variant: Variant,
    *,
    visible: tuple[Path, ...] | None = None,
    hang_after_s: float = DEFAULT_HANG_AFTER_S,
    limits: Limits | None = None,
    server: WarmJail | None = None,
) -> WorldRun:
    """Run ``mission_path`` sandboxed against this process's simulation of ``variant``.

    Args:
        spec: The test (its robot, worlds, simulated and wall-clock limits).
        mission_path: The student's mission file.
        variant: Which of the spec's runs.
        visible: Files and folders the mission process may read (default: the mission file
            and the files beside it that it names, see :func:`submission_files`).
        hang_after_s: Seconds of its own time one tick's code may run before the run is
            ``hung``.
        limits: The sandbox's resource limits.
        server: A warm jail of this student's to fork the run in (its own files, limits and
            visibility apply); by default the run gets a new jail of its own.

    Returns:
        What the world saw.
    """
    mission = Path(mission_path).resolve()
    profile = get_profile(spec.robot)
    world = spec.worlds[variant.world]
    start = Pose(*variant.start) if variant.start is not None else None
    sim = Simulation(world, profile, variant.seed, start=start)
    readable, robot_arg = _jail_files(spec, mission, visible)
    ask_short_slice()  # this world and the jail it starts take turns twice a tick
    # A file, not an argument: a world's regions can outgrow the 128 KiB an argument may hold.
    with tempfile.TemporaryDirectory(prefix="roboscript-world-") as folder:
        map_text = WorldMap.of(sim).to_json()
        if server is None:
            world_map = Path(folder) / "world-map.json"
            world_map.write_text(map_text, encoding="utf-8")
        else:
            world_map = server.share(Path(folder).name + ".json", map_text)
        ours, theirs = socket.socketpair()
        try:
            args = [
                str(mission),
                robot_arg,
                repr(spec.max_time_s),
                repr(hang_after_s),
                # the regions and the start, so in_region reads as it does in-process
                str(world_map),
            ]
            jail: Jail | JailedRun
            if server is None:
                jail = Jail(
                    [
                        sys.executable,
                        "-I",
                        "-m",
                        "roboscript.grading.mission_host",
                        str(theirs.fileno()),
                        *args,
                    ],
                    visible=tuple(dict.fromkeys([*readable, world_map])),
                    workdir=mission.parent,
                    pass_fds=(theirs.fileno(),),
                    limits=limits or Limits(),
                )
            else:  # the same student's jail, already warm: the run is a fork (fd 3 is ours)
                jail = server.start(["3", *args], pass_fds=(theirs.fileno(),), cwd=mission.parent)
        finally:
            theirs.close()
        with jail:
            handshake_s = profile.handshake_timeout_s
            session = _WorldSession(sim, spec, handshake_s, ours, jail, hang_after_s)
            try:
                return session.run()
            finally:
                ours.close()
                if server is not None:  # a later run of the same jail must not see it
                    world_map.unlink(missing_ok=True)


def _jail_files(
    spec: TestSpec, mission: Path, visible: tuple[Path, ...] | None
) -> tuple[list[Path], str]:
    """What a run's jail shows (the student's files, a teacher's robot file), and the robot
    argument of its mission process."""
    readable = list(visible if visible is not None else submission_files(mission))
    robot_file = Path(spec.robot)
    if robot_file.suffix.lower() in (".yaml", ".yml") and robot_file.is_file():
        readable.append(robot_file.resolve())  # a teacher's own profile: that file only
        return readable, str(robot_file.resolve())
    return readable, spec.robot


def warm_jail(
    spec: TestSpec,
    mission_path: str,
    *,
    visible: tuple[Path, ...] | None = None,
    limits: Limits | None = None,
) -> WarmJail:
    """A jail for several runs of ``mission_path`` on ``spec``'s robot (pass it to
    :func:`run_world` as ``server``): it shows what :func:`run_world` would show each run.

    Raises:
        As :class:`~roboscript.grading.sandbox.WarmJail`.
    """
    mission = Path(mission_path).resolve()
    readable, robot_arg = _jail_files(spec, mission, visible)
    ask_short_slice()  # inherited by the jail: its runs and this world take turns twice a tick
    return WarmJail(
        "roboscript.grading.mission_host",
        [robot_arg],
        visible=tuple(dict.fromkeys(readable)),
        workdir=mission.parent,
        limits=limits or Limits(),
    )


class _WorldSession:
    """The world's loop for one run: answer the wire, watch the clock, drain the output."""

    def __init__(
        self,
        sim: Simulation,
        spec: TestSpec,
        handshake_s: float,
        sock: socket.socket,
        jail: Jail | JailedRun,
        hang_after_s: float,
    ) -> None:
        self.sim = sim
        self.spec = spec
        self.sock = sock
        self.jail = jail
        self.hang_after_s = hang_after_s
        self.decoder = FrameDecoder(Kind.FROM_MISSION)
        self.claims = _Claims()
        self.now_s = 0.0
        self.limit_s = handshake_s + _HANDSHAKE_SLACK_S
        self.time_up = False
        self.opened = False
        self.loaded = False
        self.host_bytes = 0
        self.backlog = bytearray()  # answers the mission has not taken yet
        self.start_pose = (sim.body.x_mm, sim.body.y_mm)
        self.stall = _Stall(jail.pid)
        self.claimed_state: str | None = None  # the last state the mission reported
        # Frames come from this process's simulation only, never from the mission's process.
        self.replay = WorldReplay(sim, sim.profile)

    # ------------------------------------------------------------------------------- loop

    def run(self) -> WorldRun:
        started = now = time.monotonic()
        wall_deadline = started + self.spec.wall_time_limit_s
        self.sock.setblocking(False)
        poller = select.poll()
        poller.register(self.sock, select.POLLIN)
        for fd in self.jail.fileno_list():
            poller.register(fd, select.POLLIN)
        sock_fd = self.sock.fileno()
        recv = self.sock.recv
        ready_in = select.POLLIN | select.POLLHUP | select.POLLERR
        writing = False
        stall = self.stall
        next_slow_check = started + _SLOW_CHECK_EVERY_S
        # Every clock rule is checked at this time, not on each tick: an honest run ticks
        # hundreds of times between two checks, and each rule counts time, not ticks.
        next_check = min(stall.next_check, wall_deadline)
        # The wall-clock limit counts only time when neither side waited for a CPU.
        own = CodeClock()
        own_start_s = own.now()
        waited_start_s = _waited_s(self.jail.pid) or 0.0
        while True:
            if bool(self.backlog) != writing:
                writing = bool(self.backlog)
                poller.modify(sock_fd, select.POLLIN | (select.POLLOUT if writing else 0))
            wait_ms = (next_check - now) * 1000
            socket_ready = socket_writable = False
            for fd, mask in poller.poll(wait_ms) if wait_ms > 0 else ():
                if fd == sock_fd:
                    socket_ready = bool(mask & ready_in)
                    socket_writable = bool(mask & select.POLLOUT)
                else:
                    self.jail.drain()
            if socket_writable:
                self._flush()
            if socket_ready:
                try:
                    data = recv(_READ_CHUNK)
                except BlockingIOError:
                    data = None
                except OSError:
                    data = b""
                if data is not None:
                    if not data:
                        return self._ended()
                    try:
                        self._handle(data)
                    except _HungWhileLoadingError as exc:
                        return self._stopped("hung", f"the mission stopped while loading: {exc}")
                    except _LoadFailedError as exc:
                        return self._invalid(str(exc))
                    except _ViolationError as exc:
                        return self._broken(str(exc))
                    if self.claims.finish is not None:
                        return self._finished()
                    if self.time_up:
                        return self._out_of_time()
            now = time.monotonic()
            if now < next_check:
                continue
            if now >= wall_deadline:
                waited_s = (_waited_s(self.jail.pid) or waited_start_s) - waited_start_s
                elapsed_s = own.now() - own_start_s - waited_s
                if elapsed_s >= self.spec.wall_time_limit_s:
                    return self._stopped("timeout", self._timeout_message())
                wall_deadline = now + max(self.spec.wall_time_limit_s - elapsed_s, _CHECK_EVERY_S)
            if now >= stall.next_check:
                held = self._memory_held_bytes()
                if held is not None and held > self.jail.limits.total_memory_bytes:
                    return self._stopped("crashed", self._memory_message(held))
                allowance = 2 * self.hang_after_s + 1.0 if self.loaded else _LOAD_CPU_S
                stalled_s = stall.check(now, allowance, self.now_s)
                if stalled_s is not None:
                    return self._stopped("hung", self._hung_message(stalled_s, stall.measured))
                if stall.paused_for_s(now) >= _PAUSED_FOR_S:
                    return self._stopped("hung", self._paused_message())
            if self.loaded and now >= next_slow_check:
                next_slow_check = now + _SLOW_CHECK_EVERY_S
                used_s = stall.used_since_loaded()
                advanced_s = self.now_s - stall.loaded_at_s
                if used_s is not None and used_s > TICK_BUDGET.cpu_allowance_s(advanced_s):
                    return self._stopped("too slow", _cpu_hog_message(used_s, advanced_s))
            next_check = min(stall.next_check, wall_deadline)
            if self.loaded:
                next_check = min(next_check, next_slow_check)

    # ----------------------------------------------------------------------------- frames

    def _handle(self, data: bytes) -> None:
        try:
            frames = list(self.decoder.feed(data))
        except FrameError as exc:
            raise _ViolationError(f"it broke the grading wire ({exc})") from None
        # An honest mission asks one question and reads its answer before the next, and the
        # answer goes out only once this read is done: a read holding many questions comes
        # from a mission that does not wait for its answers. Ended here, at once, a flood gets
        # this one sentence however busy the machine (before, its unread answers had to pile
        # up first, and a flood its own load limit cut short meanwhile read as a broken wire
        # or a hang). A few at once are let through, to be judged frame by frame.
        many = len(frames) > _MAX_QUESTIONS_AT_ONCE
        if many and sum(kind in _QUESTIONS for kind, _ in frames) > _MAX_QUESTIONS_AT_ONCE:
            raise _ViolationError(_NOT_READING)
        for kind, payload in frames:
            self._frame(kind, payload)
            if self.claims.finish is not None or self.time_up:
                return

    def _frame(self, kind: bytes, payload: bytes) -> None:
        sim = self.sim
        # Nearly every frame is a tick or the host's bytes: they are asked about first.
        if kind == Kind.TICK:
            self._advance(decode_time_checked(payload))
        elif kind == Kind.WRITE:
            self.host_bytes += len(payload)
            if self.host_bytes > _MAX_HOST_BYTES:
                raise _ViolationError("it sent the robot far more bytes than any mission needs")
            sim.write(payload)
            if sim.in_waiting > _MAX_BOARD_QUEUE_BYTES:
                raise _ViolationError(
                    "it sent the robot commands far faster than it read the answers"
                )
        elif kind == Kind.SYNC:
            self._answer()
        elif kind == Kind.OPEN:
            if not self.opened:
                self.opened = True
                sim.connect()
            self._answer()
        elif kind == Kind.LOADED:
            info = _json(payload)
            name = info.get("mission") if isinstance(info, dict) else None
            self.claims.mission = _name(name) if isinstance(name, str) else ""
            self.loaded = True
            self.stall.mission_loaded(self.now_s)
        elif kind == Kind.LOAD_ERROR:
            info = _json(payload)
            message = info.get("message") if isinstance(info, dict) else None
            more = info.get("more", 0) if isinstance(info, dict) else 0
            text = _text(message if isinstance(message, str) else "", _REASON_CHARS)
            if isinstance(more, int) and more > 0:
                text += f" (and {more} more)"
            if isinstance(info, dict) and info.get("code_stopped") == "hung":
                raise _HungWhileLoadingError(text)
            raise _LoadFailedError(text)
        elif kind == Kind.START:
            if self.claims.started_s is not None:
                raise _ViolationError("it started its mission twice")
            self._check_still()
            self.claims.started_s = self.now_s
            self.limit_s = self.now_s + self.spec.max_time_s + _TIME_SLACK_S
            sim.start_mission()
            self.replay.start(self.now_s)
        elif kind == Kind.STATE:
            self._state(payload)
        elif kind == Kind.PRINT:
            self.replay.printed(self.now_s, _printed(payload))
        elif kind == Kind.FINISH:
            info = _json(payload)
            if not isinstance(info, dict):
                raise _ViolationError("its final report was not an object")
            self.claims.finish = info

    def _answer(self) -> None:
        # Never more than a frame holds; the rest waits for the next answer.
        self._reply(Kind.OUTPUT, self.sim.read(min(self.sim.in_waiting, MAX_PAYLOAD_BYTES)))

    def _reply(self, kind: bytes, payload: bytes = b"") -> None:
        """Send an answer, or what the socket takes of it now and queue the rest; never wait
        for the mission."""
        frame = encode_frame(kind, payload)
        if not self.backlog:  # the mission took every answer before: it most likely takes this
            try:
                sent = self.sock.send(frame)
            except BlockingIOError:
                sent = 0
            except OSError:  # the process is gone; the next read sees its end
                return
            if sent == len(frame):
                return
            frame = frame[sent:]
        had_backlog = bool(self.backlog)
        self.backlog += frame
        if not had_backlog:  # else the socket was full a moment ago: the loop sends when it can
            self._flush()
        if len(self.backlog) > _MAX_BACKLOG_BYTES:
            raise _ViolationError(_NOT_READING)

    def _flush(self) -> None:
        while self.backlog:
            try:
                sent = self.sock.send(self.backlog)
            except BlockingIOError:
                return
            except OSError:  # the process is gone; the next read sees its end
                self.backlog.clear()
                return
            del self.backlog[:sent]

    def _advance(self, now_s: float) -> None:
        if now_s < self.now_s:
            raise _ViolationError("its clock went backwards")
        if now_s > self.limit_s:
            self.sim.tick(self.limit_s, 0.0)
            self.now_s = self.limit_s
            self.time_up = True
            self._reply(Kind.STOPPED)
            return
        self.sim.tick(now_s, 0.0)
        self.now_s = now_s
        self.replay.tick(now_s, self.claimed_state)
        self._answer()

    def _check_still(self) -> None:
        x, y = self.start_pose
        moved = ((self.sim.body.x_mm - x) ** 2 + (self.sim.body.y_mm - y) ** 2) ** 0.5
        if moved > _START_SLACK_MM:
            raise _ViolationError(f"the robot moved {moved:.0f} mm before its mission started")

    def _state(self, payload: bytes) -> None:
        head, _, account = payload.partition(b"\n")
        name = _name(head.decode("utf-8", "replace"))
        if not name:
            raise _ViolationError("it reported a state with no name")
        if len(self.claims.states) >= MAX_GRADED_STATES:
            self.claims.dropped_states += 1
            return
        before = self.claimed_state
        start = self.claims.started_s if self.claims.started_s is not None else self.now_s
        self.claims.states.append((round(self.now_s - start, 3), name))
        self.claimed_state = name
        self.replay.enter(self.now_s, name, *_state_account(account, before))

    # ----------------------------------------------------------------------------- endings

    def _finished(self) -> WorldRun:
        info = self.claims.finish or {}
        outcome = info.get("outcome")
        stopped = info.get("code_stopped")
        if outcome not in MISSION_OUTCOMES:
            return self._broken(f"it reported an unknown outcome {_text(str(outcome), 40)!r}")
        if self.claims.started_s is None or not self.claims.states:
            return self._broken("it reported an end before its mission had started")
        last = self.claims.states[-1][1]
        final_state = info.get("final_state")
        if not isinstance(final_state, str) or _name(final_state) != last:
            return self._broken("its final state is not the last state it entered")
        self._wait_exit()
        code_error = info.get("code_error") is True
        reason = info.get("reason")
        record = self._record(
            outcome, last, _text(reason, _REASON_CHARS) if isinstance(reason, str) else None
        )
        if stopped in ("hung", "too slow"):
            # The mission process ended its own code (it may only make its own run worse).
            run = self._judged_record(record, ended_normally=False)
            run.status = "hung" if stopped == "hung" else "too slow"
            run.message = record.reason or f"the mission's code was stopped ({stopped})"
            return run
        if code_error:
            run = self._judged_record(record, ended_normally=False)
            run.status = "crashed"
            run.message = f"the run crashed: {record.reason or 'the mission raised an exception'}"
            return run
        # The mission's own limit stops it on the tick at max_time.
        return self._judged_record(record, ended_normally=ended_in_time(record, self.spec))

    def _out_of_time(self) -> WorldRun:
        """The run ran out of simulated time (the world stopped it)."""
        self.jail.kill()
        reason = f"the mission did not finish within {self.spec.max_time_s:g} s"
        last = self.claims.states[-1][1] if self.claims.states else None
        return self._judged_record(self._record("failure", last, reason), ended_normally=False)

    def _judged_record(self, record: RunRecord, ended_normally: bool) -> WorldRun:
        replay = self.replay.finish(
            mission=record.mission,
            outcome=record.outcome,
            final_state=record.final_state,
            reason=record.reason,
            duration_s=record.duration_s,
            states=record.states,
            now_s=self.now_s,
        )
        return WorldRun(
            loaded=True,
            record=record,
            ended_normally=ended_normally,
            debug=self._output(),
            replay=replay,
        )

    def _record(self, outcome: str, final_state: str | None, reason: str | None) -> RunRecord:
        start_s = self.claims.started_s if self.claims.started_s is not None else self.now_s
        return simulation_record(
            self.sim,
            start_s,
            self.now_s,
            mission=self.claims.mission or "mission",
            outcome=outcome,
            final_state=final_state,
            reason=reason,
            states=tuple(self.claims.states),
        )

    def _wait_exit(self) -> int | None:
        """The mission process's exit status, once it has ended (``None`` when it went on and
        this side ended it)."""
        # Asleep until the process ends or writes (a jail's wait drains its output), never
        # waking on a timer meanwhile.
        status = self.jail.wait(_EXIT_GRACE_S)
        self.jail.kill()
        return status

    def _ended(self) -> WorldRun:
        """The wire closed before the mission finished."""
        status = self._wait_exit()
        output = self._output()
        return WorldRun(
            status="crashed",
            message=crash_message(self.jail.stderr, status, self.loaded),
            debug=output,
            loaded=self.loaded,
        )

    def _invalid(self, problem: str) -> WorldRun:
        self._wait_exit()
        return WorldRun(
            status="invalid",
            message=f"the mission has an error: {problem}",
            debug=self._output(),
            loaded=False,
        )

    def _broken(self, why: str) -> WorldRun:
        self.jail.kill()
        return WorldRun(
            status="crashed",
            message=f"the run was stopped: {why}",
            debug=self._output(),
            loaded=self.loaded,
        )

    def _stopped(self, status: RunStatus, message: str) -> WorldRun:
        self.jail.drain()
        self.jail.kill()
        return WorldRun(status=status, message=message, debug=self._output(), loaded=self.loaded)

    def _hung_message(self, stalled_s: float, measured: str) -> str:
        phase = "while loading" if not self.loaded else f"at {self.now_s:.2f} s of simulated time"
        return (
            f"the mission stopped advancing {phase}: its code ran for {stalled_s:.1f} s of"
            f" {measured} without returning (an endless loop?)"
        )

    def _memory_held_bytes(self) -> int | None:
        """Memory the run's processes hold together (None where the system does not tell)."""
        return None if self.jail.pid is None else process_tree_memory_bytes(self.jail.pid)

    def _memory_message(self, held_bytes: int) -> str:
        limit = self.jail.limits.total_memory_bytes
        return (
            f"the mission's processes together used {held_bytes / 1024**3:.1f} GiB of memory,"
            f" over the {limit / 1024**3:g} GiB a run may use: does it start processes that"
            " each keep a lot of data?"
        )

    def _paused_message(self) -> str:
        phase = "while loading" if not self.loaded else f"at {self.now_s:.2f} s of simulated time"
        return (
            f"the mission stopped advancing {phase}: its process was paused by a stop signal"
            " (SIGSTOP) and would never go on by itself"
        )

    def _timeout_message(self) -> str:
        limit = self.spec.wall_time_limit_s
        return (
            f"the mission did not finish within the test's limit of {limit:g} s of real time:"
            " is its code waiting (time.sleep, input()) instead of returning at once?"
        )

    def _output(self) -> str:
        parts = []
        if self.jail.stdout:
            parts.append("standard output:\n" + self.jail.stdout)
        if self.jail.stderr:
            parts.append("standard error:\n" + self.jail.stderr)
        return "\n".join(parts)


class _LoadFailedError(_ViolationError):
    """The mission process reported that the mission did not load."""


class _HungWhileLoadingError(_LoadFailedError):
    """The mission process stopped a mission file that did not return while loading."""


class _Stall:
    """CPU time the mission's process tree used since simulated time last advanced.

    Where the system does not tell a process's CPU time (no ``/proc``), wall time stands in
    for it, and the teachers' guide says verdicts there depend on the machine's load.

    Args:
        pid: The jail's first process.
    """

    def __init__(self, pid: int | None) -> None:
        self.pid = pid
        self.measured = "CPU time"
        self.next_check = time.monotonic() + _CHECK_EVERY_S
        self._seen: tuple[float, bool] | None = None  # simulated time and loading, last check
        self._loaded = False
        self._at_progress_s: float | None = None
        self._at_load_s: float | None = None
        self._last_cpu_s: float | None = None
        self._paused_since: float | None = None  # wall time a stopped process was first seen
        self.loaded_at_s = 0.0

    def _used_s(self) -> float:
        if self.measured == "CPU time" and self.pid is not None:
            used = process_tree_cpu_s(self.pid)
            if used is not None:
                self._last_cpu_s = used
                return used
            if self._last_cpu_s is not None:
                # The tree ended (its end reaches the loop through the socket): it uses no
                # more CPU. Wall time here would be compared with a CPU reading.
                return self._last_cpu_s
        self.measured = "wall time"  # never told: wall time from the first reading on
        return time.monotonic()

    def mission_loaded(self, now_s: float) -> None:
        """The mission loaded at simulated time ``now_s`` (its CPU time is read now: the
        too-slow rule counts from here)."""
        if self._at_load_s is None:
            self._at_load_s = self._used_s()
            self.loaded_at_s = now_s
            self._loaded = True

    def check(self, now: float, allowance_s: float, simulated_s: float) -> float | None:
        """The seconds used without progress, once they pass ``allowance_s``; else None.

        Progress is simulated time (``simulated_s``, which never goes back) or the mission
        having loaded since the last check: a run ticks hundreds of times between two checks,
        so it is compared here rather than on each tick.
        """
        self.next_check = now + _CHECK_EVERY_S
        seen = (simulated_s, self._loaded)
        if seen != self._seen:  # an honest run: never a reading of /proc
            self._seen = seen
            self._at_progress_s = None
            return None
        used = self._used_s()
        if self._at_progress_s is None:  # the first check since time stood still
            self._at_progress_s = used
            return None
        stalled = used - self._at_progress_s
        return stalled if stalled >= allowance_s else None

    def paused_for_s(self, now: float) -> float:
        """Wall seconds a process of the tree has been seen stopped at every check since
        simulated time last stood still (0 while it advances, or where the system does not
        tell). Read only while time stands still: an honest run never reads it."""
        if self._at_progress_s is None or self.pid is None or not process_tree_stopped(self.pid):
            self._paused_since = None
            return 0.0
        if self._paused_since is None:
            self._paused_since = now
        return now - self._paused_since

    def used_since_loaded(self) -> float | None:
        """CPU seconds used since the mission loaded (None before, or where unknown)."""
        if self._at_load_s is None or self.measured != "CPU time" or self.pid is None:
            return None
        used = process_tree_cpu_s(self.pid)
        return None if used is None else used - self._at_load_s


def _waited_s(pid: int | None) -> float | None:
    """Seconds the run's processes waited for a CPU (None where unknown)."""
    return process_tree_waited_s(pid) if pid is not None else None


def _cpu_hog_message(used_s: float, advanced_s: float) -> str:
    return (
        f"the mission was too slow: its process used {used_s:.1f} s of CPU time while the robot's"
        f" time advanced {advanced_s:.1f} s (a condition or update() must return at once)"
    )


def decode_time_checked(payload: bytes) -> float:
    """A ``T`` frame's time, which must be a finite number."""
    try:
        value = decode_time(payload)
    except FrameError as exc:
        raise _ViolationError(f"it broke the grading wire ({exc})") from None
    if not math.isfinite(value):
        raise _ViolationError("its clock is not a number")
    return value


def _json(payload: bytes) -> Any:
    try:
        return decode_json(payload)
    except FrameError as exc:
        raise _ViolationError(f"it broke the grading wire ({exc})") from None


def _text(value: str, limit: int) -> str:
    """Printable text, at most ``limit`` characters."""
    clean = "".join(c if c.isprintable() else " " for c in value[: limit + 1])
    return clean[:limit] + "…" if len(clean) > limit else clean


def _name(value: str) -> str:
    return _text(value.strip(), _NAME_CHARS)


def _printed(payload: bytes) -> str:
    """A line the mission printed, made safe to show: printable text, cut to what a record
    keeps (a longer line ends with ``…``)."""
    head = payload[: 4 * (PRINTED_LINE_CHARS + 1)]  # UTF-8 takes at most 4 bytes a character
    return printed_line(head.decode("utf-8", "replace"))


def _state_account(account: bytes, before: str | None) -> tuple[str | None, dict[str, Any] | None]:
    """The action and the cause a state's report claims, made safe to show (display only).

    ``before`` is the state the world itself recorded last: the cause's ``from``. An account
    that is too long or not JSON is shown as nothing, and never ends the run: it judges nothing.
    """
    if not account or len(account) > STATE_CLAIM_BYTES:
        return None, None
    try:
        info = decode_json(account)
    except FrameError:
        return None, None
    if not isinstance(info, dict):
        return None, None
    action = info.get("action")
    cause = TransitionCause.from_claim(info.get("why"), source=before)
    return (
        _name(action) if isinstance(action, str) else None,
        None if cause is None else cause.to_json(),
    )


_TRACE_LINE = re.compile(r'^\s*File "(?P<file>[^"]+)", line (?P<line>\d+)(?:,| in) (?P<func>.*)$')
_EXCEPTION_LINE = re.compile(
    r"^(?P<type>[A-Za-z_][\w.]*(?:Error|Exception|Exit|Interrupt|Warning))"
)


_CRASHED_INSIDE = (
    "Python itself crashed: code that reaches past Python (ctypes) or a recursion limit set"
    " too high (sys.setrecursionlimit) can do that"
)
_KILLED_WHY = {
    "SIGKILL": "its own code may have sent it, or it used more memory or CPU time than a run may",
    "SIGXCPU": "it used more CPU time than a run may",
    "SIGSEGV": _CRASHED_INSIDE,
    "SIGBUS": _CRASHED_INSIDE,
    "SIGABRT": _CRASHED_INSIDE + ", and so does os.abort()",
}


def _killed_by(signum: int) -> str:
    """Why a mission process a signal killed ended, in one clause: the grader never sends
    one to a run it has not already ended itself, so it came from the kernel or the
    mission's own processes."""
    name = signal_name(signum)
    why = _KILLED_WHY.get(name, "its own code sent it (the grader sends a run no signal)")
    return f"its process was killed by {name} ({why})"


def crash_message(stderr: str, exit_status: int | None, loaded: bool) -> str:
    """One sentence for a mission process that ended before its mission finished
    (``exit_status``: None when it went on running without its wire, and was ended)."""
    phase = "" if loaded else " while loading"
    lines = [line for line in stderr.splitlines() if line.strip()]
    where = ""
    for line in lines:
        match = _TRACE_LINE.match(line)
        if match and is_student_file(match["file"]):
            where = f" ({Path(match['file']).name}:{match['line']})"
    for line in reversed(lines):
        if _EXCEPTION_LINE.match(line):
            return f"the run crashed{phase}: {_text(line.strip(), _REASON_CHARS)}{where}"
    if exit_status is None or (
        exit_status == WIRE_LOST_EXIT and lines and lines[-1] == WIRE_LOST
    ):  # its wire closed under it, or it closed its wire and went on without it
        return f"the run crashed{phase}: {WIRE_BROKEN}"
    # SIGINT is never the grader's (a jail has no terminal): mission_host says whose it was
    if exit_status - 128 in OUTSIDE_SIGNALS:
        reason = Interrupted(exit_status - 128).reason
        if lines and lines[-1] == reason:  # ended on a signal's sentence (mission_host)
            return f"the run crashed{phase}: {reason}"
    if exit_status < 0:
        return f"the run crashed{phase}: {_killed_by(-exit_status)}"
    return (
        f"the run stopped unexpectedly{phase} (its process ended with exit code {exit_status}"
        " before the mission finished): does the mission call exit()?"
    )


def submission_files(mission: Path, exclude: frozenset[Path] = frozenset()) -> tuple[Path, ...]:
    """The files a mission may read in a graded run: itself and the files near it it names.

    A mission that stands alone in a folder shared with other students' files sees only the
    files (beside it or in its sub-folders, e.g. ``behaviours/zigzag.py``) whose names or
    module names appear in its own text, and in theirs in turn; never a file in ``exclude``
    nor anything inside a folder in ``exclude`` (the other students' missions and folders,
    the test specs).

    Args:
        mission: The mission file.
        exclude: Files and folders the student must not see.
    """
    mission = mission.resolve()
    folder = mission.parent
    candidates = []
    for path in sorted(folder.rglob("*"))[:_MAX_CANDIDATES]:
        resolved = path.resolve()
        if not path.is_file() or resolved in exclude:
            continue
        if any(parent in exclude for parent in resolved.parents):
            continue
        candidates.append((path.relative_to(folder).as_posix(), resolved))
    return named_files(mission, candidates)
